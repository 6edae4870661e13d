// SHA-256 (FIPS 180-4) of a byte string, as 64 lowercase hex digits: the generated files'
// preamble names the model file's hash, so a header says which model bytes it came from.
// Small enough to write here rather than add a dependency for it.
#pragma once

#include <string>

namespace mechgen {

std::string Sha256Hex(const std::string& bytes);

}  // namespace mechgen
