// core/interrupt.hpp: a signal inside a guarded scope is recorded (not acted on), the first one is
// kept, and the handlers that were installed before the guard are back after it; a signal that ends
// the process while an AtomicFile is open leaves no temporary (remove_temporary_files_on_signal).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/interrupt.hpp"

namespace test_interrupt {

using namespace spinmotor;

namespace {

volatile sig_atomic_t g_outer = 0;  // what the handler installed before the guard saw
extern "C" void outer_handler(int sig) { g_outer = sig; }

void (*current_handler(int sig))(int) {
  struct sigaction sa = {};
  sigaction(sig, nullptr, &sa);
  return sa.sa_handler;
}

}  // namespace

TEST_CASE("a signal inside an InterruptGuard only sets the flag, and the first signal is kept",
          "[core][interrupt]") {
  InterruptGuard guard;
  CHECK(interrupted() == 0);
  REQUIRE(raise(SIGINT) == 0);  // the handler runs before raise returns; without it the test would die
  CHECK(interrupted() == SIGINT);
  REQUIRE(raise(SIGTERM) == 0);
  CHECK(interrupted() == SIGINT);
  CHECK(interrupted_exit_code(SIGINT) == 130);
  CHECK(interrupted_exit_code(SIGTERM) == 143);
  CHECK(signal_name(SIGTERM) == "SIGTERM");
}

TEST_CASE("InterruptGuard restores the previous handlers and clears the flag of an earlier run",
          "[core][interrupt]") {
  struct sigaction sa = {}, saved_int = {}, saved_term = {};
  sa.sa_handler = outer_handler;
  sigemptyset(&sa.sa_mask);
  REQUIRE(sigaction(SIGINT, &sa, &saved_int) == 0);
  REQUIRE(sigaction(SIGTERM, &sa, &saved_term) == 0);
  {
    InterruptGuard guard;
    CHECK(current_handler(SIGINT) != outer_handler);
    CHECK(current_handler(SIGTERM) != outer_handler);
    {
      InterruptGuard nested;  // a nested guard gives its outer guard's handler back
      raise(SIGTERM);
    }
    CHECK(current_handler(SIGTERM) != outer_handler);
    CHECK(interrupted() == SIGTERM);
    CHECK(g_outer == 0);  // the signal was recorded, not passed on
  }
  CHECK(current_handler(SIGINT) == outer_handler);
  CHECK(current_handler(SIGTERM) == outer_handler);
  CHECK(interrupted() == SIGTERM);  // still readable after the guard, for the exit code
  raise(SIGINT);
  CHECK(g_outer == SIGINT);  // the outer handler is live again
  {
    InterruptGuard next;  // a new run starts uninterrupted
    CHECK(interrupted() == 0);
  }
  sigaction(SIGINT, &saved_int, nullptr);
  sigaction(SIGTERM, &saved_term, nullptr);
}

TEST_CASE("a signal while files are written removes their temporaries and ends the process by that signal",
          "[core][interrupt][atomic_file]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("spinmotor_signal_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const int sig : {SIGINT, SIGTERM}) {
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {  // the child: two files in flight, then the signal (as from a Ctrl-C)
      remove_temporary_files_on_signal();
      AtomicFile a(dir / "a.obj"), b(dir / "b.obj");
      a.stream() << "v 0 0 0\n";
      a.stream().flush();
      int files = 0;
      for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
      if (files != 2) ::_exit(3);  // both temporaries must exist before the signal
      ::raise(sig);
      ::_exit(4);  // not reached: the handler ends the process by the signal
    }
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    INFO("signal " << sig << ", status " << status);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(fs::is_empty(dir));
  }
  fs::remove_all(dir);
}

}  // namespace test_interrupt
