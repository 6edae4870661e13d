/**
 * \file study/shards.h
 * A study's work in chunks, and the shards that keep it (docs/studies.md, "Resuming"): the
 * samples 0..count-1 are cut into chunks of `chunk` consecutive samples (the size depends on
 * the study only, never on threads or ranks), each chunk is evaluated by one rank's threads,
 * and its results are written, as soon as the chunk is done, to a shard file in the shard
 * directory: <dir>/chunk-<index>.bin, written whole to a temporary and renamed. A study that is
 * interrupted or killed and run again reads the shards that match it (the directory's
 * study.key: a hash of the study file, the model's parameters and nominal figures, the chunk
 * size, the samples' nominals and the values of the first 64 samples and the last: Study::Key) and evaluates only the chunks that have none; the results, and so every
 * output, are the same bytes as an uninterrupted run, whatever the threads and ranks of each.
 *
 * A shard holds its samples exactly (the doubles' bits): per sample the status code, the
 * metrics, the envelope's path. Its header names the study's key, the chunk and the layout; a
 * checksum (Mix64 over the data) follows the data. A shard that does not match (another study,
 * truncated, damaged) is not used: its chunk is evaluated again and the shard rewritten.
 * Shards are renamed into place without an fsync (study.key is synced): a killed process leaves
 * them whole in the page cache, and what a power loss can leave (an empty or torn file under
 * the final name) fails the header or checksum and is run again. One fsync per chunk cost
 * ~4 ms of a worker's time here (a 125-chunk sweep: 0.5 s of 1.1 s on one thread).
 */
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mechgen/core/random.h"

namespace mechgen::study {

/// The chunks of a study: chunk c holds the samples [c * size, min((c + 1) * size, count)).
struct Chunks {
  uint64_t count = 0;  ///< samples
  uint64_t size = 1;   ///< samples per chunk
  uint64_t number() const { return size == 0 ? 0 : (count + size - 1) / size; }
  uint64_t begin(uint64_t c) const { return c * size; }
  uint64_t end(uint64_t c) const { return std::min(count, (c + 1) * size); }
};

/// The default chunk size of `count` samples: about 256 chunks, 64 to 65536 samples each (a
/// function of the study alone, so that a resumed study finds its chunks whatever its ranks).
inline uint64_t DefaultChunkSize(uint64_t count) {
  uint64_t size = (count + 255) / 256;
  if (size < 64) size = 64;
  if (size > 65536) size = 65536;
  return size;
}

/// The status of a sample as a code in a shard (and a gather): the strings of SampleResult.
inline double StatusCode(const char* status) {
  const std::string s = status;
  return s == "ok"                  ? 0
         : s == "rows_failed"       ? 1
         : s == "not_assembled"     ? 2
         : s == "cycle_failed"      ? 4
         : s == "simulation_failed" ? 5
                                    : 3;
}
inline const char* StatusOfCode(double code) {
  return code == 0   ? "ok"
         : code == 1 ? "rows_failed"
         : code == 2 ? "not_assembled"
         : code == 4 ? "cycle_failed"
         : code == 5 ? "simulation_failed"
                     : "not_run";
}

/// A running hash of a study's identity (Mix64 chained over 64-bit words).
class KeyHash {
 public:
  void Add(uint64_t word) { h_ = Mix64(h_ ^ word); }
  void Add(double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    Add(bits);
  }
  void Add(const std::string& bytes) {
    Add(static_cast<uint64_t>(bytes.size()));
    for (unsigned char c : bytes) Add(static_cast<uint64_t>(c));
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 0x6d656368676e6b31ULL;  // "mechgnk1"
};

inline std::string Hex(uint64_t x) {
  char buffer[20];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(x));
  return buffer;
}

/// The shard directory of one study: its key, the layout of a sample (`width` doubles) and
/// the chunks.
class ShardDirectory {
 public:
  ShardDirectory(std::string dir, uint64_t key, const Chunks& chunks, uint64_t width)
      : dir_(std::move(dir)), key_(key), chunks_(chunks), width_(width) {}

  const std::string& dir() const { return dir_; }

  /// Creates the directory and its study.key, or checks that an existing one is this study's.
  /// False and *error when it holds another study's shards (they are left alone) or cannot be
  /// made.
  bool Open(std::string* error) const {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) return *error = "cannot create the shard directory " + dir_ + ": " + ec.message(), false;
    const std::string path = dir_ + "/study.key", want = KeyText();
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::ostringstream text;
      text << in.rdbuf();
      if (text.str() == want) return true;
      return *error = "the shard directory " + dir_ +
                      " holds the shards of another study (its study.key differs: the study file, the model, "
                      "the chunk size or the samples changed); remove it, or give another --shards",
             false;
    }
    return WriteWhole(path, want.data(), want.size(), /*sync=*/true, error);
  }

  std::string Path(uint64_t c) const {
    char name[40];
    std::snprintf(name, sizeof name, "/chunk-%08llu.bin", static_cast<unsigned long long>(c));
    return dir_ + name;
  }

  /// Reads chunk c's shard into part[0, samples * width); false if there is none or it does
  /// not match this study (then nothing is changed).
  bool Read(uint64_t c, double* out) const {
    std::ifstream in(Path(c), std::ios::binary);
    if (!in) return false;
    const uint64_t n = chunks_.end(c) - chunks_.begin(c);
    uint64_t header[6];
    if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return false;
    if (header[0] != kMagic || header[1] != key_ || header[2] != c || header[3] != chunks_.begin(c) ||
        header[4] != n || header[5] != width_)
      return false;
    std::vector<double> part(n * width_);
    uint64_t sum = 0;
    if (!in.read(reinterpret_cast<char*>(part.data()), static_cast<std::streamsize>(part.size() * sizeof(double))) ||
        !in.read(reinterpret_cast<char*>(&sum), sizeof sum) || in.peek() != std::char_traits<char>::eof())
      return false;
    if (sum != Checksum(part.data(), part.size())) return false;
    std::memcpy(out, part.data(), part.size() * sizeof(double));
    return true;
  }

  /// Writes chunk c's shard from part[0, samples * width) (whole, then renamed).
  bool Write(uint64_t c, const double* part, std::string* error) const {
    const uint64_t n = chunks_.end(c) - chunks_.begin(c);
    const uint64_t header[6] = {kMagic, key_, c, chunks_.begin(c), n, width_};
    std::string bytes(reinterpret_cast<const char*>(header), sizeof header);
    bytes.append(reinterpret_cast<const char*>(part), n * width_ * sizeof(double));
    const uint64_t sum = Checksum(part, n * width_);
    bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
    return WriteWhole(Path(c), bytes.data(), bytes.size(), /*sync=*/false, error);
  }

  /// Removes the shards and study.key, then the directory if it is empty.
  void Remove() const {
    std::error_code ec;
    for (uint64_t c = 0; c < chunks_.number(); ++c) std::filesystem::remove(Path(c), ec);
    std::filesystem::remove(dir_ + "/study.key", ec);
    std::filesystem::remove(dir_, ec);  // only if empty
  }

 private:
  static constexpr uint64_t kMagic = 0x3144485354534d47ULL;  // "GMSTSHD1"

  static uint64_t Checksum(const double* x, uint64_t n) {
    KeyHash h;
    for (uint64_t i = 0; i < n; ++i) h.Add(x[i]);
    return h.value();
  }

  std::string KeyText() const {
    return "mechgen study shards 1\nkey " + Hex(key_) + "\nsamples " + std::to_string(chunks_.count) + "\nchunk " +
           std::to_string(chunks_.size) + "\nwidth " + std::to_string(width_) + "\n";
  }

  // `bytes` into `path`: a temporary beside it (unique to this process and thread), written,
  // synced if `sync` and renamed (a reader, or a run after a kill, sees the whole file or none).
  static bool WriteWhole(const std::string& path, const char* bytes, size_t size, bool sync, std::string* error) {
    std::string tmp = path + ".tmp.XXXXXX";
    const int fd = mkstemp(&tmp[0]);
    if (fd < 0) return *error = "cannot write " + path + ": " + std::strerror(errno), false;
    size_t done = 0;
    while (done < size) {
      const ssize_t w = ::write(fd, bytes + done, size - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) break;
      done += static_cast<size_t>(w);
    }
    const int saved = done < size ? errno : 0;
    const bool ok = done == size && (!sync || ::fsync(fd) == 0);
    ::close(fd);
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
      *error = "cannot write " + path + ": " + std::strerror(saved != 0 ? saved : errno);
      std::remove(tmp.c_str());
      return false;
    }
    return true;
  }

  std::string dir_;
  uint64_t key_;
  Chunks chunks_;
  uint64_t width_;
};

}  // namespace mechgen::study
