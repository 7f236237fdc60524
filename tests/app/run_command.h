// Runs the built `brushtrace` executable as a user runs it, for the command-line tests.
#pragma once

#include <string>

namespace bt::test {

struct CommandResult {
  int exitCode = -1;
  std::string out; // stdout
  std::string err; // stderr
};

// `args` is appended to the executable's path as shell words (quote paths yourself). stdout
// and stderr go to files, so the command sees no terminal, as under CI.
CommandResult brushtrace(const std::string& args);
// Any shell command line, its output captured the same way (a browser, a Slurm client).
CommandResult runShell(const std::string& command);

} // namespace bt::test
