/**
 * \file io/output_file.h
 * OutputFile: an output file that is either whole or absent. The tools (<model>_sweep,
 * <model>_statics, <model>_simulate, <model>_engine) write every CSV and SVG through it:
 *  - Open() creates a temporary file next to the destination (same directory, so that the
 *    final rename() is atomic: ".<name>.tmp.XXXXXX", via mkstemp), creating the parent
 *    directory; the destination is not touched yet.
 *  - stream() is a std::ostream over that file; every write() failure (ENOSPC, EIO, EDQUOT,
 *    ...) is remembered with its errno.
 *  - Commit() flushes, fsyncs and closes the temporary file and renames it onto the
 *    destination. Any failure on the way (write, flush, fsync, close, rename) returns false
 *    with "cannot write <path>: <strerror>" and removes the temporary file: the
 *    destination then is exactly what it was before (absent, or the previous whole file).
 *  - Close() is Commit() without the rename: a tool writing several files closes each (every
 *    write checked) before it renames any, so that one failure leaves none of them changed.
 *  - Discard() (and the destructor, when Commit() was not called) removes the temporary.
 * A destination that exists and is not a regular file (/dev/stdout, /dev/full, a FIFO;
 * a symbolic link counts as what it points to, and a link to a regular file is replaced
 * by the new file) is written directly, with the same error checks: it cannot be
 * replaced by a rename, and holds no file to leave partial. The new file gets the
 * permissions a plain open() would give (0666 minus the umask).
 * POSIX only; allocates (a tool's output, never in a solver's hot path); not thread-safe
 * (reads the umask by setting it).
 */
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace mechgen {

namespace internal {

/// A std::streambuf writing to a file descriptor through a buffer; remembers the errno of
/// the first failed write(2).
class FdStreamBuf : public std::streambuf {
 public:
  FdStreamBuf() : buffer_(1 << 16) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  void set_fd(int fd) { fd_ = fd; }
  /// errno of the first failure, 0 if none.
  int error() const { return error_; }
  /// Writes the buffer out; false on failure (error() says why).
  bool Drain() {
    const char* p = pbase();
    size_t left = static_cast<size_t>(pptr() - pbase());
    while (left > 0 && error_ == 0) {
      const ssize_t n = ::write(fd_, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
      } else if (n == 0) {
        error_ = EIO;
      } else {
        p += n;
        left -= static_cast<size_t>(n);
      }
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return error_ == 0;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!Drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return Drain() ? 0 : -1; }

 private:
  std::vector<char> buffer_;
  int fd_ = -1;
  int error_ = 0;
};

}  // namespace internal

/// A file written whole or not at all (see the file comment).
class OutputFile {
 public:
  OutputFile() : stream_(&buf_) {}
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile() { Discard(); }

  /// Opens the temporary file for `path` (or `path` itself, see the file comment). False
  /// with "cannot write <path>: <reason>" in *error; nothing is created then.
  bool Open(const std::string& path, std::string* error) {
    Discard();
    path_ = path;
    namespace fs = std::filesystem;
    if (path.empty()) return Fail("empty file name", error);
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) {
      if (S_ISDIR(st.st_mode)) return Fail(std::strerror(EISDIR), error);
      if (!S_ISREG(st.st_mode)) {  // a device or FIFO: written in place
        fd_ = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd_ < 0) return Fail(std::strerror(errno), error);
        direct_ = true;
        buf_.set_fd(fd_);
        return true;
      }
    }
    const fs::path target(path);
    const fs::path parent = target.parent_path();
    if (!parent.empty()) {
      std::error_code ec;
      fs::create_directories(parent, ec);
      if (ec) return Fail(ec.message(), error);
    }
    const std::string name = target.filename().string();
    if (name.empty() || name == "." || name == "..") return Fail(std::strerror(EISDIR), error);
    std::string temp = (parent.empty() ? std::string() : parent.string() + "/") + "." + name +
                       ".tmp.XXXXXX";
    std::vector<char> pattern(temp.begin(), temp.end());
    pattern.push_back('\0');
    fd_ = ::mkstemp(pattern.data());
    if (fd_ < 0) return Fail(std::strerror(errno), error);
    temp_ = pattern.data();
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd_, 0666 & ~mask);
    buf_.set_fd(fd_);
    return true;
  }

  /// Where to write (valid after a successful Open()).
  std::ostream& stream() { return stream_; }
  /// The destination path.
  const std::string& path() const { return path_; }

  /// Flushes, fsyncs and closes the temporary file without renaming it yet (the first half
  /// of Commit(), so that a tool writing several files checks every one before any is put in
  /// place); false with "cannot write <path>: <reason>" in *error (the temporary file is
  /// then removed). Commit() afterwards only renames.
  bool Close(std::string* error) {
    if (closed_) return true;
    if (fd_ < 0) return Fail("not open", error);
    stream_.flush();
    int failure = buf_.Drain() ? 0 : buf_.error();
    if (failure == 0 && !stream_) failure = EIO;
    if (failure == 0 && !direct_ && ::fsync(fd_) != 0) failure = errno;
    if (::close(fd_) != 0 && failure == 0) failure = errno;
    fd_ = -1;
    if (failure != 0) {
      Discard();
      return Fail(std::strerror(failure), error);
    }
    closed_ = true;
    return true;
  }

  /// Flushes, closes (Close()) and renames onto the destination; false with "cannot write
  /// <path>: <reason>" in *error (the temporary file is then removed).
  bool Commit(std::string* error) {
    if (!Close(error)) return false;
    if (!direct_ && std::rename(temp_.c_str(), path_.c_str()) != 0) {
      const int failure = errno;
      Discard();
      return Fail(std::strerror(failure), error);
    }
    temp_.clear();
    direct_ = false;
    closed_ = false;
    return true;
  }

  /// Closes and removes the temporary file, if any; the destination is untouched.
  void Discard() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (!temp_.empty()) ::unlink(temp_.c_str());
    temp_.clear();
    direct_ = false;
    closed_ = false;
  }

 private:
  bool Fail(const std::string& reason, std::string* error) {
    if (error != nullptr) *error = "cannot write " + path_ + ": " + reason;
    return false;
  }

  internal::FdStreamBuf buf_;
  std::ostream stream_;
  std::string path_;
  std::string temp_;
  int fd_ = -1;
  bool direct_ = false;
  bool closed_ = false;  ///< Close() succeeded; Commit() renames
};

}  // namespace mechgen
