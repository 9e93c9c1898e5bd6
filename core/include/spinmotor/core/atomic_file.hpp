#pragma once
// Atomic file output: nothing the project writes is ever left half-written.
//
// AtomicFile opens a temporary file next to the target (same directory, hence same file system),
// hands out an std::ofstream to it, and commit() flushes, checks the stream, closes, fsyncs and
// renames the temporary over the target (rename(2) is atomic on POSIX: a reader sees the old file
// or the complete new one). If the object is destroyed without commit() — an exception while
// writing, an early return — the temporary is removed and the target is untouched.
//
//   AtomicFile out(path);            // creates missing parent directories
//   out.stream() << ...;             // may throw: the target is left as it was
//   out.commit();                    // throws spinmotor::Error naming the path on any I/O failure
//
// Every writer in the project (meshes, JSON reports, images) goes through this class or
// write_text_atomic().
#include <filesystem>
#include <fstream>
#include <string_view>

namespace spinmotor {

class AtomicFile {
 public:
  /// Opens a temporary file in target's directory (created if missing). `binary` selects
  /// std::ios::binary (no newline translation; it makes no difference on POSIX).
  /// Throws Error naming the path if the directory cannot be created or the file cannot be opened.
  explicit AtomicFile(std::filesystem::path target, bool binary = true);
  ~AtomicFile();  ///< removes the temporary file unless commit() succeeded

  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The stream to write to (the temporary file).
  std::ofstream& stream() { return out_; }

  /// Flushes, closes and renames the temporary over the target. Throws Error naming the target if
  /// any write failed (disk full, ...); the temporary is then removed and the target untouched.
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temp_path() const { return temp_; }
  bool committed() const { return committed_; }

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  ///< entry in the table remove_temporary_files_on_signal() reads, or -1
};

/// Writes `text` to `path` atomically (via AtomicFile). Throws Error naming the path on failure.
void write_text_atomic(const std::filesystem::path& path, std::string_view text);

/// For a program's main(): from now on SIGINT, SIGTERM and SIGHUP remove the temporary files of the
/// AtomicFiles in flight, then end the process by the same signal (its default action: the parent sees
/// "killed by SIGINT", as without the handler). Without it a Ctrl-C while a mesh is written leaves a
/// ".<name>.<pid>...tmp" next to the target (the target itself is never half-written either way).
/// An InterruptGuard (interrupt.hpp) replaces these handlers for its lifetime and restores them.
/// Up to 64 temporaries in flight are tracked (more are still removed by their destructors, but not
/// on a signal).
void remove_temporary_files_on_signal();

}  // namespace spinmotor
