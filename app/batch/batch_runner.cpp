#include "app/batch/batch_runner.h"

#include "app/batch/batch_files.h"
#include "app/batch/batch_level.h"

#include <fmt/format.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace bt::app::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Slurm's scancel and requeue, and Ctrl-C, stop a batch with SIGTERM or SIGINT. A signal
// handler can only set a flag of static storage; the runner then kills the level's child and
// leaves without writing a result for it, so a requeued run redoes that level.
volatile std::sig_atomic_t stopRequested = 0;
extern "C" void requestStop(int) {
  stopRequested = 1;
}

void installStopHandlers() {
  struct sigaction action {};
  action.sa_handler = requestStop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

const char* const kResultVersion = "brushtrace batch 1"; // part of the job hash: a new format reruns

std::string jobHash(const Level& level, const Jobs& jobs) {
  return sha256Hex(std::string(kResultVersion) + toJson(jobs).dump() + level.entry.dump());
}

bool upToDate(const std::string& resultPath, const std::string& hash) {
  const auto result = readJsonFile(resultPath);
  if (!result || result->value("job_hash", "") != hash || !result->contains("inputs")) return false;
  std::vector<std::string> files;
  for (const auto& input : result->at("inputs")) files.push_back(input.value("path", ""));
  return result->value("input_hash", "") == inputHash(hashInputs(files), hash);
}

// In the child: limits, output to the level's log, the jobs, the result file. Never returns.
[[noreturn]] void runChild(const Level& level, const Manifest& manifest, const fs::path& work) {
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGINT, SIG_DFL);
  if (manifest.limits.memoryMb > 0) {
    const rlim_t bytes = rlim_t(manifest.limits.memoryMb) << 20;
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
  }
  const int log = open((work / "log.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (log >= 0) dup2(log, STDOUT_FILENO), dup2(log, STDERR_FILENO), close(log);
  try {
    const json result = runLevelJobs(level, manifest.jobs, work.string(), "images/" + level.id + "/");
    writeJsonAtomically((work / "result.json").string(), result);
    std::fflush(nullptr);
    _exit(0);
  } catch (const std::exception& e) {
    fmt::print(stderr, "brushtrace batch: {}\n", e.what());
  }
  std::fflush(nullptr);
  _exit(3);
}

// The last lines a failed child printed, for its failure message.
std::string logTail(const fs::path& log) {
  std::ifstream in(log);
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text.size() > 600 ? "..." + text.substr(text.size() - 600) : text;
}

// Waits for the child up to the level's time limit; "" when it finished, else why not.
std::string waitForChild(pid_t child, double limitSeconds) {
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // A child that ended between two polls but past the limit still took too long.
    if (done == child && (elapsed <= limitSeconds || stopRequested)) break;
    if (done == child) return fmt::format("timed out after {:g} s (limits.seconds)", limitSeconds);
    if (stopRequested || elapsed > limitSeconds) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      return stopRequested ? "stopped" : fmt::format("timed out after {:g} s (limits.seconds)", limitSeconds);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // scancel signals every process of the task at once: the child may die of it before this
  // process sees its own SIGTERM. Either way the level was stopped, not failed.
  if (stopRequested || (WIFSIGNALED(status) && (WTERMSIG(status) == SIGTERM || WTERMSIG(status) == SIGINT))) return "stopped";
  if (WIFSIGNALED(status)) return fmt::format("crashed: killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  if (WEXITSTATUS(status) != 0) return fmt::format("the level's process exited with status {}", WEXITSTATUS(status));
  return "";
}

// Runs one level in a child process and returns its result; nullopt when the batch was stopped.
std::optional<json> runLevel(const Level& level, const Manifest& manifest, const fs::path& work) {
  fs::remove_all(work);
  fs::create_directories(work / "images");
  std::fflush(nullptr); // the child must not print the parent's buffered lines again
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error(fmt::format("cannot start a process for {}: {}", level.path, std::strerror(errno)));
  if (child == 0) runChild(level, manifest, work);
  const std::string problem = waitForChild(child, manifest.limits.seconds);
  if (problem == "stopped") return std::nullopt;
  if (problem.empty())
    if (auto result = readJsonFile((work / "result.json").string())) return result;
  const std::string tail = logTail(work / "log.txt");
  return failedLevel(level, "process",
                     problem.empty() ? "no result written" : problem + (tail.empty() ? "" : "; its last output: " + tail));
}

// A result and its images take their place: the images first, the result last, so a result
// on disk always has its images. A kill between the two leaves images a rerun replaces.
void publish(const Level& level, json result, const std::string& hash, const fs::path& work, const fs::path& out) {
  result["job_hash"] = hash;
  result["input_hash"] = inputHash(result.at("inputs"), hash);
  const fs::path images = out / "images" / level.id;
  fs::remove_all(images);
  if (result.contains("renders") && !result["renders"].empty()) {
    fs::create_directories(images.parent_path());
    fs::rename(work / "images", images);
  }
  writeJsonAtomically((out / "levels" / (level.id + ".json")).string(), result);
  fs::remove_all(work);
}

// What a killed run of this slice left: its levels' work folders and temporary result files.
void removeLeftovers(const std::vector<Level>& levels, const fs::path& out) {
  for (const Level& level : levels) fs::remove_all(out / "tmp" / level.id);
  for (const auto& entry : fs::directory_iterator(out / "levels")) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 4 && name.ends_with(".tmp"))
      for (const Level& level : levels)
        if (name.starts_with("." + level.id + ".json.")) fs::remove(entry.path());
  }
}

void printProgress(const Level& level, const json& result, const char* how, size_t done, size_t total, int failed) {
  const bool ok = result.value("status", "") == "ok";
  std::string line = fmt::format("{:<7} {}", ok ? how : "FAILED", level.path);
  if (!ok && !result["failures"].empty())
    line += fmt::format(": {}: {}", result["failures"][0].value("job", ""), result["failures"][0].value("message", ""));
  else
    line += fmt::format(" ({:.2f} s)", result.value("seconds", 0.0));
  fmt::print("{}\n[{:3.0f}%] {}/{} levels, {} failed\n", line, 100.0 * double(done) / double(total), done, total, failed);
  std::fflush(stdout); // piped to a log or a Slurm output file, each line shows as it happens
}

} // namespace

int runBatch(const Manifest& manifest, const RunOptions& options) {
  installStopHandlers();
  const fs::path out = options.outDir;
  fs::create_directories(out / "levels");
  const std::vector<Level> levels = shardOf(manifest.levels, options.shard, options.shards);
  removeLeftovers(levels, out);
  int failed = 0;
  for (size_t i = 0; i < levels.size(); ++i) {
    const Level& level = levels[i];
    const std::string hash = jobHash(level, manifest.jobs);
    const std::string resultPath = (out / "levels" / (level.id + ".json")).string();
    const char* how = "skipped";
    if (!upToDate(resultPath, hash)) {
      const fs::path work = out / "tmp" / level.id;
      const std::optional<json> result = runLevel(level, manifest, work);
      if (!result) {
        fs::remove_all(work);
        return -1;
      }
      publish(level, *result, hash, work, out);
      how = "ok";
    }
    const json result = readJsonFile(resultPath).value_or(json::object());
    failed += result.value("status", "") != "ok";
    printProgress(level, result, how, i + 1, levels.size(), failed);
    if (stopRequested) return -1;
  }
  std::error_code ec;
  fs::remove(out / "tmp", ec); // only when empty: another shard may be working in it
  return failed;
}

} // namespace bt::app::batch
