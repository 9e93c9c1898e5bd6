// core/interrupt.hpp: a signal inside a guarded scope is recorded (not acted on), the first one is
// kept, and the handlers that were installed before the guard are back after it; a signal that ends
// the process while an AtomicFile is open leaves no temporary (remove_temporary_files_on_signal);
// DeferStopSignals holds a stop signal back and delivers it to the project's handler afterwards, with
// the handlers as they were whatever a dependency did meanwhile; under take_stop_signals() a signal
// thread takes every stop signal, whatever handler is installed.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <thread>

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

int current_flags(int sig) {
  struct sigaction sa = {};
  sigaction(sig, nullptr, &sa);
  return sa.sa_flags;
}

bool blocked_here(int sig) {
  sigset_t mask;
  pthread_sigmask(SIG_BLOCK, nullptr, &mask);
  return sigismember(&mask, sig) == 1;
}

extern "C" void dependency_handler(int) { ::_exit(5); }  // what METIS's would do: not the project's

/// Waits up to 2 s for interrupted() to become nonzero (the signal thread records asynchronously).
int wait_interrupted() {
  const auto t0 = std::chrono::steady_clock::now();
  while (!interrupted() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return interrupted();
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

TEST_CASE("SIGHUP is a stop request: recorded by an InterruptGuard, exit code 129", "[core][interrupt]") {
  InterruptGuard guard;
  REQUIRE(raise(SIGHUP) == 0);
  CHECK(interrupted() == SIGHUP);
  CHECK(interrupted_exit_code(SIGHUP) == 129);
  CHECK(signal_name(SIGHUP) == "SIGHUP");
}

TEST_CASE(
    "DeferStopSignals: a stop signal waits for the end of the scope, then reaches the project's handler",
    "[core][interrupt]") {
  InterruptGuard guard;
  const int flags = current_flags(SIGTERM);
  CHECK((flags & SA_RESTART) != 0);
  CHECK_FALSE(blocked_here(SIGTERM));
  {
    DeferStopSignals defer;
    CHECK_FALSE(defer.already_blocked());
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) CHECK(blocked_here(sig));
    // A dependency replaces the handler, then puts it back as signal(2) does with System V semantics
    // (one-shot, no SA_RESTART): GKlib's gk_sigtrap / gk_siguntrap around every METIS ordering.
    struct sigaction dep = {};
    dep.sa_handler = dependency_handler;
    sigemptyset(&dep.sa_mask);
    dep.sa_flags = SA_RESETHAND | SA_NODEFER;
    struct sigaction ours = {};
    REQUIRE(sigaction(SIGTERM, &dep, &ours) == 0);
    REQUIRE(raise(SIGTERM) == 0);  // pending: blocked on this thread, so the dependency never sees it
    ours.sa_flags = SA_RESETHAND | SA_NODEFER;
    REQUIRE(sigaction(SIGTERM, &ours, nullptr) == 0);
    {
      DeferStopSignals nested;
      CHECK(nested.already_blocked());
    }
    CHECK(blocked_here(SIGTERM));  // the nested guard leaves the outer one's mask
    CHECK(interrupted() == 0);
  }
  CHECK(interrupted() == SIGTERM);  // delivered as the guard ended, to the recording handler
  CHECK(current_handler(SIGTERM) != dependency_handler);
  CHECK(current_flags(SIGTERM) == flags);  // exactly as before: SA_RESTART back, not one-shot
  CHECK_FALSE(blocked_here(SIGTERM));
}

TEST_CASE("take_stop_signals: one thread takes every stop signal, whatever handler is installed",
          "[core][interrupt][atomic_file]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("spinmotor_taken_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {  // the child: a program's main()
    take_stop_signals();
    if (!stop_signals_taken() || !blocked_here(SIGTERM) || !blocked_here(SIGINT) || !blocked_here(SIGHUP))
      ::_exit(10);
    {
      InterruptGuard guard;
      struct sigaction dep = {};  // a dependency's handler, installed while the run is in its code
      dep.sa_handler = dependency_handler;
      sigemptyset(&dep.sa_mask);
      sigaction(SIGTERM, &dep, nullptr);
      ::kill(::getpid(), SIGTERM);  // to the process, as from a scheduler
      if (wait_interrupted() != SIGTERM) ::_exit(11);
      ::kill(::getpid(), SIGINT);  // later signals change nothing and stop nothing
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      if (interrupted() != SIGTERM) ::_exit(12);
    }
    // No guard: the temporaries go and the process ends by the signal.
    AtomicFile a(dir / "a.obj");
    a.stream() << "v 0 0 0\n";
    a.stream().flush();
    ::kill(::getpid(), SIGHUP);
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ::_exit(13);  // not reached
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  INFO("status " << status);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGHUP);
  CHECK(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace test_interrupt
