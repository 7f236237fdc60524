// brushtrace batch on a real Slurm: a one-node cluster started by scripts/slurm/local-cluster.sh
// (munged, slurmctld, slurmd from Debian's slurm-wlm), a 4-task job array over 40 shared maps
// with one task cancelled half-way and requeued, merged to the report of a run on this machine.
#include "tests/app/batch_support.h"
#include "tests/app/run_command.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <thread>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using bt::test::brushtrace;
using nlohmann::json;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// A command's stdout (sbatch, squeue, scontrol), or "" when it fails.
std::string capture(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

// Starts the cluster and stops it (daemons gone, state removed) whatever the test does.
class LocalSlurm {
public:
  explicit LocalSlurm(fs::path state) : state_(std::move(state)) {
    const std::string out = capture("bash " + q(script()) + " start " + q(state_));
    started_ = out.find("export SLURM_CONF=") != std::string::npos;
    if (started_) setenv("SLURM_CONF", (state_ / "slurm.conf").c_str(), 1);
  }
  ~LocalSlurm() {
    if (std::system(("bash " + q(script()) + " stop " + q(state_)).c_str()) != 0) ADD_FAILURE() << "local-cluster.sh stop failed";
    unsetenv("SLURM_CONF");
  }
  bool started() const { return started_; }

private:
  static fs::path script() { return bt::test::sourceDir() / "scripts" / "slurm" / "local-cluster.sh"; }
  fs::path state_;
  bool started_ = false;
};

template <class Done> bool waitFor(Done done, std::chrono::seconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return true;
}

// 40 shared maps: 39 spread over the sorted list of the small ones (every dialect among them)
// and, last of task 2's ten, LibreQuake's lqdm5, whose faithful render takes 10-30 s here (the
// lightmap bake): the level task 2 is cancelled in. Shard 2 of 4 holds indices 1, 5, ..., 37.
json manifestOf40(const fs::path& shared) {
  std::vector<std::string> maps;
  for (const auto& e : fs::recursive_directory_iterator(shared / "maps"))
    if (e.path().extension() == ".map" && e.path().string().find("librequake") == std::string::npos) maps.push_back(e.path().string());
  std::sort(maps.begin(), maps.end());
  json levels = json::array();
  for (size_t i = 0; i < 39; ++i) levels.push_back(maps[i * maps.size() / 39]);
  levels.insert(levels.begin() + 37, (shared / "maps" / "librequake" / "lq1" / "maps" / "src" / "dm" / "lqdm5.map").string());
  return {{"levels", levels}, {"jobs", {{"render", {{"size", "32x18"}, {"spp", 1}, {"backend", "cpu"}}}}}};
}

TEST(SlurmBatch, AnArrayWithOneTaskCancelledAndRequeuedMergesToTheSingleMachineReport) {
  BT_REQUIRE_SHARED(shared);
  if (!fs::exists("/usr/sbin/slurmctld") || !fs::exists("/usr/sbin/munged") || geteuid() != 0)
    GTEST_SKIP() << "needs root and Debian's slurm-wlm and munge (apt-get install slurm-wlm munge): the one-node cluster is not started";
  const fs::path dir = bt::test::freshTempDir("slurm");
  // Removed after the cluster has stopped (declared first, destroyed last): the stop reads its pid files.
  const std::shared_ptr<void> removeDir(nullptr, [&dir](void*) { fs::remove_all(dir); });
  bt::test::writeText(dir / "m.json", manifestOf40(shared).dump(1));
  const auto single = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "single"));
  ASSERT_LE(single.exitCode, 1) << single.err;

  LocalSlurm slurm(dir / "slurm-state");
  ASSERT_TRUE(slurm.started()) << bt::test::readText(dir / "slurm-state" / "slurmctld.log");
  const auto submit = brushtrace("batch " + q(dir / "m.json") + " -o " + q(dir / "cluster") + " --slurm --shards 4 --submit");
  ASSERT_EQ(submit.exitCode, 0) << submit.err << submit.out;
  const std::string array = submit.out.substr(0, submit.out.find('\n'));
  const fs::path log2 = dir / "cluster" / "slurm" / (array + "_2.out");

  // Task 2 is cancelled in its last level, lqdm5, once it has finished the nine before it,
  // requeued, and let start at once (a requeued job is otherwise held for two minutes).
  ASSERT_TRUE(waitFor([&] { return bt::test::readText(log2).find("9/10 levels") != std::string::npos; }, std::chrono::seconds(240)))
      << bt::test::readText(log2);
  ASSERT_EQ(std::system(("scancel " + array + "_2").c_str()), 0);
  ASSERT_TRUE(waitFor([&] { return capture("squeue -h -t R -j " + array + "_2").empty(); }, std::chrono::seconds(60)));
  ASSERT_EQ(std::system(("scontrol requeue " + array + "_2").c_str()), 0);
  // The hold is set a moment after the requeue returns: update until the task is no longer pending.
  waitFor(
      [&] {
        std::system(("scontrol update jobid=" + array + "_2 starttime=now 2>/dev/null").c_str());
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        return capture("squeue -h -t PD -j " + array + "_2").empty();
      },
      std::chrono::seconds(150));
  ASSERT_TRUE(waitFor([&] { return capture("squeue -h").empty(); }, std::chrono::seconds(420))) << capture("squeue");

  const std::string log = bt::test::readText(log2);
  EXPECT_NE(log.find("CANCELLED"), std::string::npos) << log;
  EXPECT_NE(log.find("restart 1"), std::string::npos) << log;
  // The second run skipped the nine levels the first finished and did lqdm5, once.
  const size_t restart = log.find("restart 1");
  EXPECT_EQ(log.find("lqdm5.map ("), log.rfind("lqdm5.map (")) << log;
  EXPECT_GT(log.find("lqdm5.map ("), restart) << log;
  size_t skipped = 0;
  for (size_t at = log.find("\nskipped "); at != std::string::npos; at = log.find("\nskipped ", at + 1)) ++skipped;
  EXPECT_EQ(skipped, 9u) << log;
  ASSERT_TRUE(fs::is_regular_file(dir / "cluster" / "report.json")) << "the merge job wrote no report";
  const json report = bt::test::readJson(dir / "cluster" / "report.json");
  EXPECT_EQ(report.at("levels").size(), 40u);
  EXPECT_EQ(bt::test::withoutTimings(report), bt::test::withoutTimings(bt::test::readJson(dir / "single" / "report.json")));
  EXPECT_EQ(bt::test::partialFiles(dir / "cluster"), std::vector<fs::path>{});
}

} // namespace
