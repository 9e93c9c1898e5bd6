// `spinmotor batch`: run one subcommand over many meshes, one process per mesh, N at a time, resumable.
//
//   spinmotor batch --run "SUBCOMMAND ARGS" --out-dir DIR [--jobs N] [--suffix .obj] [--list FILE]
//       [--grace SECONDS] [--json] [-q] MESH...
// ARGS contain {in} and {out} ({stem} is the input's file stem); --run is split into words like a
// shell would (quotes and backslashes; no expansion).
//
// Each input runs `spinmotor SUBCOMMAND ARGS` with {in} = the input path and {out} = DIR/<stem><suffix>,
// its stdout and stderr going to DIR/logs/<stem>.log. Every spinmotor command writes its outputs
// atomically (temp file + rename), so an output that exists is complete: inputs whose output exists are
// skipped, and a batch that was interrupted (or killed by a scheduler) resumes where it stopped by
// running the same command again. One failing mesh does not stop the others; the exit code is the
// worst one of the runs (0 all ok, 2 a bad input, 3 a numerical failure). Progress lines with elapsed
// time and ETA go to stderr unless -q. SIGINT, SIGTERM or SIGHUP (to the batch alone or to its process
// group) stops it: nothing more is started, the running commands get the signal and remove their
// temporary files; a command still running --grace seconds later (default 10) is killed (SIGKILL) and
// its temporary of {out} removed by the batch; the summary counts the interrupted, killed and not-run
// inputs, and the exit code is 128 + signal.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"

extern char** environ;

namespace spinmotor::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct BatchArgs {
  int jobs = 2;
  double grace = 10;  // seconds a command has to stop after a stop signal is passed on
  std::string out_dir, suffix = ".obj", list, run;
  std::vector<std::string> inputs;
  bool json = false, quiet = false;
};

struct Job {
  fs::path input, output, log;
  std::string status = "pending";  // pending, skipped, ok, failed, interrupted, killed
  int exit_code = 0;
  double seconds = 0;
};

/// Splits a command line into words: whitespace separates, '...' and "..." group, \ escapes.
std::vector<std::string> split_words(const std::string& s) {
  std::vector<std::string> words;
  std::string w;
  bool in_word = false;
  char quote = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == quote)
        quote = 0;
      else if (c == '\\' && quote == '"' && i + 1 < s.size())
        w += s[++i];
      else
        w += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (c == '\\' && i + 1 < s.size()) {
      w += s[++i];
      in_word = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (in_word) words.push_back(w), w.clear(), in_word = false;
    } else {
      w += c;
      in_word = true;
    }
  }
  if (quote) throw Error(std::string("batch: --run has an unterminated ") + quote + " quote");
  if (in_word) words.push_back(w);
  return words;
}

std::string substitute(std::string s, const Job& j) {
  const std::pair<std::string, std::string> keys[] = {
      {"{in}", j.input.string()}, {"{out}", j.output.string()}, {"{stem}", j.input.stem().string()}};
  for (const auto& [k, v] : keys)
    for (std::size_t p = s.find(k); p != std::string::npos; p = s.find(k, p + v.size()))
      s.replace(p, k.size(), v);
  return s;
}

/// The path of this executable (the batch runs the same binary for every mesh).
std::string self_path() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw numerical_error("batch: cannot find the spinmotor executable (/proc/self/exe)");
  return p.string();
}

pid_t spawn(const std::string& exe, const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  // The command starts with the stop signals unblocked: the batch blocks them in every thread
  // (take_stop_signals, main.cpp), and a signal mask is inherited.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t mask;
  pthread_sigmask(SIG_BLOCK, nullptr, &mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigdelset(&mask, sig);
  posix_spawnattr_setsigmask(&attr, &mask);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, exe.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw numerical_error("batch: cannot start " + exe + ": " + std::strerror(rc));
  return pid;
}

/// Removes what the command of process `pid` left of its AtomicFile temporaries of `output`
/// (".<name>.<pid>.<counter>.<random>.tmp" next to it, core/atomic_file.cpp): a killed command cannot.
void remove_temporaries(const fs::path& output, pid_t pid) {
  const std::string prefix = "." + output.filename().string() + "." + std::to_string(pid) + ".";
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0)
      fs::remove(e.path(), ec);
  }
}

std::string duration(double s) {
  char b[32];
  if (s < 60)
    std::snprintf(b, sizeof b, "%.1f s", s);
  else
    std::snprintf(b, sizeof b, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return b;
}

/// The command template, checked: words, {in} and {out} present, not batch itself.
std::vector<std::string> command_words(const BatchArgs& a) {
  const std::vector<std::string> command = split_words(a.run);
  if (command.empty())
    throw Error("batch: --run is empty (e.g. --run \"spin {in} --rho-expr 0.5*z --out {out}\")");
  if (command[0] == "batch") throw Error("batch: the command cannot be batch itself");
  bool has_in = false, has_out = false;
  for (const std::string& s : command) {
    has_in = has_in || s.find("{in}") != std::string::npos;
    has_out = has_out || s.find("{out}") != std::string::npos;
  }
  if (!has_in || !has_out)
    throw Error("batch: the command must contain {in} and {out} (the input mesh and the output path)");
  return command;
}

/// One job per input (MESH... then the --list file), skipped where the output exists.
std::vector<Job> collect_jobs(const BatchArgs& a, const fs::path& out_dir, const fs::path& logs) {
  std::vector<std::string> inputs = a.inputs;
  if (!a.list.empty()) {
    std::ifstream in(a.list);
    if (!in) throw Error("batch: cannot read the list file " + a.list);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      inputs.push_back(line);
    }
  }
  if (inputs.empty()) throw Error("batch: no input meshes (give MESH... or --list FILE)");
  std::vector<Job> jobs;
  std::map<std::string, std::string> stems;
  for (const std::string& in : inputs) {
    Job j;
    j.input = in;
    if (!fs::exists(j.input)) throw Error("batch: input " + in + " does not exist");
    const std::string stem = j.input.stem().string();
    if (auto [it, fresh] = stems.emplace(stem, in); !fresh)
      throw Error("batch: inputs " + it->second + " and " + in + " would write the same output (stem '" +
                  stem + "')");
    j.output = out_dir / (stem + a.suffix);
    j.log = logs / (stem + ".log");
    if (fs::exists(j.output)) j.status = "skipped";  // atomic outputs: existing means complete
    jobs.push_back(std::move(j));
  }
  return jobs;
}

/// Runs the pending jobs, a.jobs at a time, until all have ended or a stop signal has ended the
/// running ones. SIGINT / SIGTERM / SIGHUP: launch nothing more, pass the signal on to the running
/// commands (a Ctrl-C in a terminal reaches them too; a scheduler's SIGTERM may reach the batch alone),
/// wait for them (each removes its temporaries and stops within a second or two), and kill the ones
/// still running a.grace seconds after the signal (SIGKILL; the batch then removes their temporaries
/// of {out}). Running the same command again resumes.
void run_jobs(const BatchArgs& a, const std::vector<std::string>& command, std::vector<Job>& jobs) {
  const std::string exe = self_path();
  struct Running {
    std::size_t job;
    Clock::time_point start;
    bool killed = false;
  };
  std::map<pid_t, Running> running;
  const auto t0 = Clock::now();
  std::size_t next = 0, done = 0, todo = 0;
  for (const Job& j : jobs) todo += j.status == "pending";
  auto report_progress = [&](const Job& j) {
    if (a.quiet) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    const double eta =
        done < todo ? elapsed / static_cast<double>(done) * static_cast<double>(todo - done) : 0.0;
    std::cerr << "batch: [" << done << "/" << todo << "] " << j.input.filename().string() << " " << j.status
              << " (" << duration(j.seconds) << ", exit " << j.exit_code << "); elapsed " << duration(elapsed)
              << (done < todo ? ", ETA " + duration(eta) : std::string()) << '\n';
  };
  const InterruptGuard guard;
  std::optional<Clock::time_point> forwarded;
  while (true) {
    if (const int sig = interrupted(); sig && !forwarded) {
      for (const auto& [pid, r] : running) ::kill(pid, sig);
      forwarded = Clock::now();
    }
    if (forwarded && Clock::now() - *forwarded > std::chrono::duration<double>(a.grace))
      for (auto& [pid, r] : running)
        if (!r.killed) ::kill(pid, SIGKILL), r.killed = true;
    while (!interrupted() && static_cast<int>(running.size()) < std::max(1, a.jobs) && next < jobs.size()) {
      Job& j = jobs[next];
      if (j.status == "pending") {
        std::vector<std::string> args;
        for (const std::string& s : command) args.push_back(substitute(s, j));
        running[spawn(exe, args, j.log)] = {next, Clock::now()};
      }
      ++next;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);  // polled, so that a signal is seen at once
    if (pid < 0) throw numerical_error("batch: waitpid failed");
    if (pid == 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    Job& j = jobs[it->second.job];
    j.seconds = std::chrono::duration<double>(Clock::now() - it->second.start).count();
    j.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    j.status = j.exit_code == 0    ? "ok"
               : it->second.killed ? "killed"
               : interrupted()     ? "interrupted"
                                   : "failed";
    if (it->second.killed) remove_temporaries(j.output, pid);
    running.erase(it);
    ++done;
    report_progress(j);
  }
}

/// Prints the summary (text, or JSON with --json) and throws what the exit code says: Interrupted
/// after a stop signal, Error for the worst failure.
void report(const BatchArgs& a, const std::vector<Job>& jobs, const fs::path& logs, double total) {
  int worst = 0;
  std::map<std::string, int> counts;
  nlohmann::json runs = nlohmann::json::array();
  for (const Job& j : jobs) {
    ++counts[j.status];
    if (j.status == "failed") worst = std::max(worst, j.exit_code == 2 || j.exit_code == 3 ? j.exit_code : 3);
    runs.push_back({{"input", j.input.string()},
                    {"output", j.output.string()},
                    {"status", j.status},
                    {"exit_code", j.exit_code},
                    {"seconds", j.seconds},
                    {"log", j.log.string()}});
  }
  const int killed = counts["killed"];
  const std::string grace = duration(a.grace);
  if (a.json) {
    std::cout << nlohmann::json{{"inputs", jobs.size()},
                                {"ok", counts["ok"]},
                                {"skipped", counts["skipped"]},
                                {"failed", counts["failed"]},
                                {"interrupted", counts["interrupted"]},
                                {"killed", killed},
                                {"not_run", counts["pending"]},
                                {"seconds", total},
                                {"runs", runs}}
                     .dump(2)
              << '\n';
  } else if (!a.quiet) {
    std::cout << "batch: " << jobs.size() << " inputs: " << counts["ok"] << " ok, " << counts["skipped"]
              << " skipped (output exists), " << counts["failed"] << " failed"
              << (interrupted() ? ", " + std::to_string(counts["interrupted"]) + " interrupted, " +
                                      (killed ? std::to_string(killed) + " killed (still running " + grace +
                                                    " after the signal), "
                                              : std::string()) +
                                      std::to_string(counts["pending"]) + " not run"
                                : std::string())
              << ", in " << duration(total) << '\n';
    for (const Job& j : jobs)
      if (j.status == "failed" || j.status == "killed")
        std::cout << "  " << j.status << " (exit " << j.exit_code << "): " << j.input.string() << ", see "
                  << j.log.string() << '\n';
  }
  if (const int sig = interrupted())
    throw Interrupted(
        sig, "batch stopped with " + std::to_string(counts["ok"]) + " of " + std::to_string(jobs.size()) +
                 " outputs written" +
                 (killed ? " (" + std::to_string(killed) + (killed == 1 ? " command" : " commands") +
                               " killed, still running " + grace + " after the signal)"
                         : std::string()) +
                 "; run the same command again to resume");
  if (worst != 0)
    throw Error("batch: " + std::to_string(counts["failed"]) + " of " + std::to_string(jobs.size()) +
                    " runs failed (logs in " + logs.string() + ")",
                worst == 2 ? Error::Kind::BadInput : Error::Kind::Numerical);
}

void run(const BatchArgs& a) {
  const std::vector<std::string> command = command_words(a);
  const fs::path out_dir = a.out_dir, logs = out_dir / "logs";
  std::vector<Job> jobs = collect_jobs(a, out_dir, logs);
  fs::create_directories(logs);
  const auto t0 = Clock::now();
  run_jobs(a, command, jobs);
  report(a, jobs, logs, std::chrono::duration<double>(Clock::now() - t0).count());
}

const RegisterCommand register_batch{
    "batch", "Run one subcommand over many meshes, one process per mesh, N at a time; resumable",
    [](CLI::App& sub) {
      auto a = std::make_shared<BatchArgs>();
      sub.add_option("MESH", a->inputs, "Input meshes");
      sub.add_option("--run", a->run, "The subcommand and its arguments, with {in}, {out} and {stem}")
          ->required();
      sub.add_option("--list", a->list, "Text file with one input mesh per line ('#' comments)");
      sub.add_option("--out-dir", a->out_dir, "Directory of the outputs ({out}) and of logs/")->required();
      sub.add_option("--suffix", a->suffix, "Output file name = input stem + suffix")->capture_default_str();
      sub.add_option("-j,--jobs", a->jobs, "Processes at a time")
          ->capture_default_str()
          ->check(CLI::Range(1, 1024));
      sub.add_option("--grace", a->grace,
                     "After a stop signal (SIGINT, SIGTERM, SIGHUP), seconds a running command has to stop "
                     "before it is killed (SIGKILL)")
          ->capture_default_str()
          ->check(CLI::Range(0.0, 86400.0));
      sub.add_flag("--json", a->json, "Print a JSON summary");
      sub.add_flag("-q,--quiet", a->quiet, "No progress lines and no summary (the exit code remains)");
      sub.footer(
          "Examples:\n"
          "  spinmotor batch -j 2 --out-dir faired --run \"flow {in} --willmore 0.3 --steps 5 --out {out}\" "
          "meshes/*.obj\n"
          "  spinmotor batch --list todo.txt --out-dir snapped --run \"snap rest/{stem}.obj {in} --out "
          "{out}\"\n"
          "Run it again after an interruption: finished outputs are skipped. On a cluster, submit one job "
          "per\n"
          "mesh running the same command with a single MESH (or an array job indexing --list); outputs are "
          "atomic.");
      sub.callback([a] { run(*a); });
    }};

}  // namespace
}  // namespace spinmotor::cli
