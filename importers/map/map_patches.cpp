#include "importers/map/map_patches.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <vector>

namespace bt::map {
namespace {

// Tokens of a patch block: parentheses and braces alone, quoted names, everything else split
// at white space; each with the number of line breaks before it.
class PatchTokens {
public:
  explicit PatchTokens(std::string_view text) : text_(text) {}

  std::string_view next() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return {};
    const size_t start = pos_;
    const char c = text_[pos_];
    if (c == '(' || c == ')' || c == '{' || c == '}') return text_.substr(pos_++, 1);
    if (c == '"') {
      const size_t end = text_.find('"', pos_ + 1);
      pos_ = end == std::string_view::npos ? text_.size() : end + 1;
      return text_.substr(start + 1, pos_ - start - 2);
    }
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) && text_[pos_] != '(' && text_[pos_] != ')')
      ++pos_;
    return text_.substr(start, pos_ - start);
  }
  int line() const { return line_; }

private:
  std::string_view text_;
  size_t pos_ = 0;
  int line_ = 0;
};

bool expect(PatchTokens& tokens, std::string_view want, std::string& error) {
  const std::string_view got = tokens.next();
  if (got == want) return true;
  error = fmt::format("patch: expected '{}', found '{}'", want, got.empty() ? "end of block" : got);
  return false;
}

bool readNumbers(PatchTokens& tokens, double* out, int count, std::string& error) {
  if (!expect(tokens, "(", error)) return false;
  for (int i = 0; i < count; ++i) {
    const std::string_view token = tokens.next();
    const std::optional<double> number = quake::parseNumber(token);
    if (number) out[i] = *number;
    if (!number) {
      error = fmt::format("patch: expected a number, found '{}'", token.empty() ? "end of block" : token);
      return false;
    }
  }
  return expect(tokens, ")", error);
}

} // namespace

bool isPatchBlock(std::string_view verbatim) {
  return verbatim.starts_with("patchDef2") || verbatim.starts_with("patchDef3");
}

std::optional<MapPatch> parsePatchBlock(std::string_view verbatim, std::string& error, int& lineOffset) {
  PatchTokens tokens(verbatim);
  MapPatch patch;
  const bool def3 = tokens.next() == "patchDef3";
  auto failed = [&] {
    lineOffset = tokens.line();
    return std::nullopt;
  };
  if (!expect(tokens, "{", error)) return failed();
  patch.texture = std::string(tokens.next());
  double info[7] = {};
  if (!readNumbers(tokens, info, def3 ? 7 : 5, error)) return failed();
  // Odd sizes below 3 are refused with the tessellator's reason (patchGridProblem); sizes beyond
  // the engine's are refused before their points are read.
  if (info[0] < 1 || info[1] < 1 || info[0] > kPatchMaxGridSize || info[1] > kPatchMaxGridSize || info[0] != int(info[0]) ||
      info[1] != int(info[1])) {
    error = fmt::format("patch: a size of {} x {} control points (each side must be odd, 3 to {})", info[0], info[1], kPatchMaxGridSize);
    return failed();
  }
  patch.control.width = int(info[0]);
  patch.control.height = int(info[1]);
  patch.control.points.resize(size_t(patch.control.width) * size_t(patch.control.height));
  if (!expect(tokens, "(", error)) return failed();
  for (int j = 0; j < patch.control.width; ++j) {
    if (!expect(tokens, "(", error)) return failed();
    for (int i = 0; i < patch.control.height; ++i) {
      double v[5];
      if (!readNumbers(tokens, v, 5, error)) return failed();
      patch.control.points[size_t(i * patch.control.width + j)] = {{v[0], v[1], v[2]}, {v[3], v[4]}};
    }
    if (!expect(tokens, ")", error)) return failed();
  }
  if (!expect(tokens, ")", error) || !expect(tokens, "}", error)) return failed();
  return patch;
}

} // namespace bt::map
