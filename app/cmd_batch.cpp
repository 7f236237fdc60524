// brushtrace batch: many levels' import checks, round trips and renders into one folder, with a
// merged report and contact sheet; restartable, shardable, and submitted to Slurm as an array.
#include "app/batch/batch_manifest.h"
#include "app/batch/batch_report.h"
#include "app/batch/batch_runner.h"
#include "app/commands.h"
#include "app/usage_checks.h"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

namespace bt::app {

namespace fs = std::filesystem;

namespace {

struct BatchArgs {
  std::vector<std::string> inputs; // one .json manifest, or levels
  std::string output;
  std::string merge;
  int shard = 1, shards = 1;
  std::string backend;
  bool slurm = false, submit = false, gpu = false;
  int slurmShards = 4;
};

// --shard K/N, 1 <= K <= N, checked while the command line is parsed.
void addShardOption(CLI::App& cmd, BatchArgs& args) {
  cmd.add_option_function<std::string>(
         "--shard",
         [&args](const std::string& text) {
           char rest = 0;
           if (std::sscanf(text.c_str(), "%d/%d%c", &args.shard, &args.shards, &rest) != 2 || args.shard < 1 || args.shard > args.shards)
             throw CLI::ValidationError("--shard", "expected K/N with 1 <= K <= N, got '" + text + "'");
         },
         "Run only slice K of N (every N-th level from the K-th); merge the slices with --merge")
      ->type_name("K/N");
}

// -o DIR: an existing writable folder, or one that can be made in an existing writable folder.
CLI::Validator outputFolder() {
  return CLI::Validator([](std::string& path) { return fs::is_directory(path) ? writableFolder()(path) : outputFile()(path); }, "DIR");
}

batch::Manifest loadManifest(const BatchArgs& args, const std::map<std::string, std::string>& configured) {
  const bool isManifest = args.inputs.size() == 1 && fs::path(args.inputs[0]).extension() == ".json";
  batch::Manifest manifest = isManifest ? batch::readManifest(args.inputs[0]) : batch::manifestForLevels(args.inputs);
  for (batch::Level& level : manifest.levels) level.import.textures.game.configuredBaseDirs = configured;
  if (!args.backend.empty() && manifest.jobs.render) manifest.jobs.render->backend = args.backend;
  return manifest;
}

// Where the sbatch scripts are: the source tree's for the build tree's executable, else PREFIX/share/brushtrace/slurm.
fs::path slurmScripts() {
  std::error_code ec;
  const fs::path exeDir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (!ec && fs::equivalent(exeDir, BRUSHTRACE_BINARY_DIR, ec)) return fs::path(BRUSHTRACE_SOURCE_DIR) / "scripts" / "slurm";
  return (exeDir / BRUSHTRACE_DATA_FROM_BINDIR / "slurm").lexically_normal();
}

std::string quoted(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The job array (one task per shard) and the merge job that waits for all of it, as shell lines.
std::string slurmScript(const BatchArgs& args) {
  const fs::path scripts = slurmScripts();
  const std::string out = fs::absolute(args.output).string();
  const std::string exe = fs::read_symlink("/proc/self/exe").string();
  const std::string env = "--export=ALL,BRUSHTRACE=" + quoted(exe);
  return fmt::format("mkdir -p {0}/slurm\n"
                     "array=$(sbatch --parsable --array=1-{1} {2}--output={0}/slurm/%A_%a.out {3} {4} {5} {0} {1})\n"
                     "echo \"${{array%%;*}}\"\n"
                     "sbatch --parsable --dependency=afterany:${{array%%;*}} --output={0}/slurm/merge-%j.out {3} {6} {0}\n",
                     quoted(out), args.slurmShards, args.gpu ? "--gres=gpu:1 " : "", env, quoted((scripts / "batch-array.sbatch").string()),
                     quoted(fs::absolute(args.inputs[0]).string()), quoted((scripts / "batch-merge.sbatch").string()));
}

int submitToSlurm(const BatchArgs& args) {
  const std::string script = slurmScript(args);
  if (!args.submit) {
    fmt::print("{}", script);
    return 0;
  }
  FILE* shell = popen("sh -e", "w");
  if (!shell) throw std::runtime_error("cannot start sh to run sbatch");
  std::fputs(script.c_str(), shell);
  const int status = pclose(shell);
  if (status != 0) fmt::print(stderr, "brushtrace: batch --submit: sbatch failed (status {})\n", status);
  return status == 0 ? 0 : 1;
}

int runBatchCommand(const BatchArgs& args) {
  if (!args.merge.empty()) {
    const auto report = batch::mergeResults(args.merge);
    fmt::print("merged {} levels ({} failed) into {}\n", report["summary"]["levels"].get<size_t>(),
               report["summary"]["failed"].get<size_t>(), (fs::path(args.merge) / "report.json").string());
    return 0; // the merge did its job; the report lists the levels that failed
  }
  if (args.slurm) return submitToSlurm(args);
  const batch::Manifest manifest = loadManifest(args, configuredBaseDirs());
  const int failed = batch::runBatch(manifest, {args.output, args.shard, args.shards});
  if (failed < 0) {
    fmt::print(stderr, "brushtrace: batch stopped; run it again to finish\n");
    return 1;
  }
  if (args.shards == 1) batch::mergeResults(args.output);
  if (failed > 0)
    fmt::print(stderr, "brushtrace: batch: {} level(s) failed; see {}\n", failed,
               (fs::path(args.output) / (args.shards == 1 ? "index.html" : "levels")).string());
  return failed == 0 ? 0 : 1;
}

} // namespace

void addBatchCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd =
      app.add_subcommand("batch", "Check and render many levels: per-level results, report.json and an index.html contact sheet");
  auto args = std::make_shared<BatchArgs>();
  // A plain path must exist; ARCHIVE:maps/x.bsp, a bare level name and a glob are the importer's and the manifest's to check.
  const CLI::Validator plainPathExists(
      [](std::string& p) {
        return p.find_first_of(":*?[") != std::string::npos || (p.find('/') == std::string::npos && p.find('.') == std::string::npos)
            ? std::string()
            : CLI::ExistingPath(p);
      },
      "PATH");
  cmd->add_option("INPUT", args->inputs, "A manifest (.json), or levels (files, ARCHIVE:maps/x.bsp, globs, folders) with the default jobs")
      ->check(plainPathExists);
  cmd->add_option("-o,--output", args->output, "The folder of results (made if missing)")->type_name("DIR")->check(outputFolder());
  cmd->add_option("--merge", args->merge, "Only merge the results under DIR (every shard's) into report.json and index.html")
      ->type_name("DIR")
      ->check(writableFolder());
  addShardOption(*cmd, *args);
  cmd->add_option("--backend", args->backend, "Override the manifest's render backend: auto|gl|cpu")
      ->check(CLI::IsMember({"auto", "gl", "cpu"}));
  cmd->add_flag("--slurm", args->slurm, "Print the sbatch commands of a Slurm job array over the manifest and its merge job");
  cmd->add_option("--shards", args->slurmShards, "--slurm: array tasks, one shard each")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_flag("--gpu", args->gpu, "--slurm: ask each task for a GPU (--gres=gpu:1)");
  cmd->add_flag("--submit", args->submit, "--slurm: submit through sbatch instead of printing");
  cmd->callback([args, cmd, &exitCode] {
    const bool merging = !args->merge.empty();
    if (merging == (!args->inputs.empty() || !args->output.empty()))
      throw CLI::ValidationError("batch", merging ? "--merge DIR takes no levels and no -o" : "expected a manifest or levels, and -o DIR");
    if (!merging && args->inputs.empty()) throw CLI::ValidationError("INPUT", "expected a manifest or levels");
    if (!merging && args->output.empty()) throw CLI::ValidationError("--output", "required");
    if ((args->slurm || args->submit || args->gpu) && !(args->slurm && args->inputs.size() == 1 && args->inputs[0].ends_with(".json")))
      throw CLI::ValidationError("--slurm", "--slurm, --submit and --gpu take one manifest (.json)");
    exitCode = runBatchCommand(*args);
  });
}

} // namespace bt::app
