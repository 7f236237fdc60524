#include "tests/app/run_command.h"

#include "tests/test_data.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <unistd.h>

namespace bt::test {

namespace {
std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
} // namespace

CommandResult brushtrace(const std::string& args) {
  return runShell("'" + (binaryDir() / "brushtrace").string() + "' " + args);
}

CommandResult runShell(const std::string& command) {
  const auto dir = std::filesystem::temp_directory_path() / ("bt_app_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cmd = command + " >'" + (dir / "out").string() + "' 2>'" + (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(dir / "out");
  r.err = readFile(dir / "err");
  std::filesystem::remove_all(dir);
  return r;
}

} // namespace bt::test
