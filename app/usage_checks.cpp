#include "app/usage_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <unistd.h>
#include <vector>

namespace bt::app {

namespace fs = std::filesystem;

namespace {

// Empty when a file can be created in `folder`, else why not. A file is really made (and
// removed): permission bits do not tell, since root passes them, and neither do read-only
// mounts or /proc.
std::string folderProblem(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) return fmt::format("folder '{}' does not exist", folder.string());
  if (!fs::is_directory(folder, ec)) return fmt::format("'{}' is not a folder", folder.string());
  std::string probe = (folder / ".brushtrace-write-check-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return fmt::format("folder '{}' is not writable", folder.string());
  ::close(fd);
  ::unlink(probe.c_str());
  return {};
}

fs::path folderOf(const std::string& file) {
  const fs::path parent = fs::path(file).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

std::string lowercaseExtension(const std::string& file) {
  std::string ext = fs::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), size_t(0));
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = diagonal + (a[i - 1] != b[j - 1]);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

} // namespace

CLI::Validator levelFile() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        std::error_code ec;
        if (fs::is_directory(path, ec)) return fmt::format("'{}' is a folder, not a level file", path);
        if (fs::exists(path, ec)) return {};
        // ARCHIVE:maps/x.bsp: the archive must be there; its entry is the import's to find.
        if (const size_t colon = path.find(':'); colon != std::string::npos && colon > 0) {
          const std::string archive = path.substr(0, colon);
          if (fs::is_regular_file(archive, ec)) return {};
          return fmt::format("'{}': no such archive", archive);
        }
        // A bare level name (e1m1) is looked up in the game install by the import.
        const fs::path p(path);
        if (!p.has_parent_path() && !p.has_extension()) return {};
        return fmt::format("'{}': no such file", path);
      },
      "LEVEL");
}

CLI::Validator outputFile() {
  return CLI::Validator([](std::string& path) { return folderProblem(folderOf(path)); }, "");
}

CLI::Validator imageFile() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        const std::string ext = lowercaseExtension(path);
        if (ext != ".png" && ext != ".exr") return fmt::format("'{}': output must be .png or .exr", path);
        return folderProblem(folderOf(path));
      },
      "");
}

CLI::Validator writableFolder() {
  return CLI::Validator([](std::string& path) { return folderProblem(path); }, "");
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0)) return fmt::format("expected a number above 0, got '{}'", text);
        return {};
      },
      "POSITIVE");
}

void addCameraOption(CLI::App& command, std::optional<CameraPose>& pose, const std::string& help) {
  command
      .add_option_function<std::string>(
          "--camera",
          [&pose](const std::string& text) {
            pose = parseCameraPose(text);
            if (!pose)
              throw CLI::ValidationError("--camera",
                                         fmt::format("expected \"(x y z) pitch yaw roll\" or \"setpos x y z pitch yaw "
                                                     "roll\" (roll optional), got \"{}\"",
                                                     text));
          },
          help)
      ->type_name("POSE");
}

std::string commandList(const CLI::App& app) {
  std::string list = "commands:\n";
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    list += fmt::format("  {:<10} {}\n", command->get_name(), command->get_description());
  return list + "Run 'brushtrace COMMAND --help' for a command's options.\n";
}

bool isCommand(const CLI::App& app, const std::string& name) {
  return !app.get_subcommands([&name](const CLI::App* command) { return command->check_name(name); }).empty();
}

std::optional<std::string> nearestCommand(const CLI::App& app, std::string_view typed) {
  std::optional<std::string> best;
  size_t bestDistance = 3; // more than two edits away is not a typo of it
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string& name = command->get_name();
    const size_t distance = name.rfind(typed, 0) == 0 ? 0 : editDistance(typed, name);
    if (distance < bestDistance) best = name, bestDistance = distance;
  }
  return best;
}

} // namespace bt::app
