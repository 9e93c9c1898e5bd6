#include "spinmotor/core/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <random>
#include <string>
#include <system_error>

#include "spinmotor/core/error.hpp"
#include "temporaries.hpp"

namespace spinmotor {
namespace fs = std::filesystem;

namespace {

// A name no other writer (thread or process) uses: ".<target>.<pid>.<counter>.<random>.tmp".
fs::path temporary_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  static const unsigned seed = std::random_device{}();
  std::string name(1, '.');
  name += target.filename().string();
  for (const unsigned long long part :
       {static_cast<unsigned long long>(::getpid()), static_cast<unsigned long long>(counter++),
        static_cast<unsigned long long>(seed % 100000)}) {
    name += '.';
    name += std::to_string(part);
  }
  name += ".tmp";
  return target.parent_path() / name;
}

// Makes the temporary's data durable before the rename publishes it (otherwise a crash right after
// the rename can leave an empty target on some file systems).
void sync_file(const fs::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// The temporaries in flight, for the signal handler: fixed storage (no allocation, nothing the handler
// cannot read), a slot's path published by its state (0 free, 1 being filled, 2 readable).
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
struct TempSlot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};
TempSlot g_slots[kSlots];

int track_temporary(const fs::path& p) {
  const std::string& s = p.native();
  if (s.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
    g_slots[i].state.store(2);
    return i;
  }
  return -1;
}

void untrack_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0);
}

extern "C" void remove_temporaries_and_reraise(int sig) {
  detail::remove_temporaries_in_flight();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

void detail::remove_temporaries_in_flight() noexcept {
  for (TempSlot& t : g_slots)
    if (t.state.load() == 2) ::unlink(t.path);  // async-signal-safe
}

void remove_temporary_files_on_signal() {
  struct sigaction sa = {};
  sa.sa_handler = remove_temporaries_and_reraise;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

AtomicFile::AtomicFile(fs::path target, bool binary) : target_(std::move(target)) {
  if (target_.empty() || !target_.has_filename())
    throw Error("cannot write '" + target_.string() + "': not a file name");
  const fs::path dir = target_.parent_path();
  if (!dir.empty()) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec)
      throw Error("cannot create directory '" + dir.string() + "' for '" + target_.string() +
                  "': " + ec.message());
  }
  if (fs::is_directory(target_)) throw Error("cannot write '" + target_.string() + "': it is a directory");
  temp_ = temporary_name(target_);
  slot_ = track_temporary(temp_);  // before the file exists: a signal from here on removes it
  std::ios::openmode mode = std::ios::out | std::ios::trunc;
  if (binary) mode |= std::ios::binary;
  errno = 0;
  out_.open(temp_, mode);
  if (!out_) {
    untrack_temporary(slot_);
    throw Error("cannot open '" + temp_.string() + "' for writing (next to '" + target_.string() +
                "'): " + (errno ? std::strerror(errno) : "unknown error"));
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    if (out_.is_open()) out_.close();
    std::error_code ec;
    fs::remove(temp_, ec);  // never throws from a destructor; the temporary may not exist
  }
  untrack_temporary(slot_);
}

void AtomicFile::commit() {
  if (committed_) return;
  out_.flush();
  const bool write_ok = static_cast<bool>(out_);
  out_.close();
  if (!write_ok || out_.fail()) {
    std::error_code ec;
    fs::remove(temp_, ec);
    throw Error("cannot write '" + target_.string() + "': an output error occurred (disk full?)");
  }
  sync_file(temp_);
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) {
    std::error_code ec2;
    fs::remove(temp_, ec2);
    throw Error("cannot write '" + target_.string() +
                "': rename of the temporary file failed: " + ec.message());
  }
  committed_ = true;
  untrack_temporary(slot_);
  slot_ = -1;
}

void write_text_atomic(const fs::path& path, std::string_view text) {
  AtomicFile f(path);
  f.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
  f.commit();
}

}  // namespace spinmotor
