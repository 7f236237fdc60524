#include "quake/entity_keys.h"

#include "scene/names.h"

#include <fmt/format.h>
#include <glm/common.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace bt::quake {

namespace {

constexpr std::string_view kSpace = " \t\r\n\v\f";

std::string_view trimmed(std::string_view text, std::string_view space) {
  const size_t first = text.find_first_not_of(space);
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(space) - first + 1);
}

} // namespace

std::optional<double> parseNumber(std::string_view word) {
  const char* first = word.data();
  const char* last = first + word.size();
  if (first != last && *first == '+') ++first; // from_chars rejects '+', stod and sscanf take it
  double value = 0.0;
  const auto [end, ec] = std::from_chars(first, last, value);
  if (first == last || ec != std::errc() || end != last || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::vector<double>> parseNumbers(std::string_view text) {
  std::vector<double> numbers;
  for (size_t pos = text.find_first_not_of(kSpace); pos != std::string_view::npos; pos = text.find_first_not_of(kSpace, pos)) {
    const size_t end = std::min(text.find_first_of(kSpace, pos), text.size());
    const auto n = parseNumber(text.substr(pos, end - pos));
    if (!n) return std::nullopt;
    numbers.push_back(*n);
    pos = end;
  }
  return numbers;
}

std::optional<float> parseFloat(std::string_view text) {
  const auto n = parseNumbers(text);
  if (!n || n->size() != 1 || !std::isfinite(float((*n)[0]))) return std::nullopt;
  return float((*n)[0]);
}

std::optional<int> parseInteger(std::string_view text) {
  const auto n = parseNumbers(text);
  if (!n || n->size() != 1) return std::nullopt;
  const double v = (*n)[0];
  if (v != std::trunc(v) || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) return std::nullopt;
  return int(v);
}

std::optional<glm::dvec3> parseDvec3(std::string_view text) {
  const auto n = parseNumbers(text);
  if (!n || n->size() != 3) return std::nullopt;
  return glm::dvec3((*n)[0], (*n)[1], (*n)[2]);
}

std::optional<glm::vec3> parseVec3(std::string_view text) {
  const auto v = parseDvec3(text);
  if (!v) return std::nullopt;
  const glm::vec3 f(*v);
  if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return std::nullopt;
  return f;
}

const std::string* findKey(const KeyValues& keys, std::string_view key) {
  for (const auto& [k, v] : keys)
    if (k == key) return &v;
  for (const auto& [k, v] : keys)
    if (equalsIgnoreCase(trimmed(k, " \t"), key)) return &v;
  return nullptr;
}

int toInt(double value) {
  return static_cast<int>(std::clamp(value, -1e6, 1e6));
}

glm::vec3 normalisedColour(glm::vec3 colour) {
  if (colour.x > 1.0f || colour.y > 1.0f || colour.z > 1.0f) colour /= 255.0f;
  return glm::max(colour, glm::vec3(0.0f));
}

std::string_view EntityKeys::string(std::string_view key, std::string_view fallback) const {
  const std::string* text = find(key);
  return text ? std::string_view(*text) : fallback;
}

float EntityKeys::number(std::string_view key, float fallback) const {
  const std::string* text = find(key);
  if (!text) return fallback;
  if (auto v = parseFloat(*text)) return *v;
  warn(fmt::format("key \"{}\" has value \"{}\", expected a number; using {}", key, *text, fallback));
  return fallback;
}

int EntityKeys::integer(std::string_view key, int fallback) const {
  return toInt(number(key, float(fallback)));
}

std::optional<glm::vec3> EntityKeys::vec3(std::string_view key) const {
  const std::string* text = find(key);
  if (!text) return std::nullopt;
  if (auto v = parseVec3(*text)) return v;
  warn(fmt::format("key \"{}\" has value \"{}\", expected three numbers; ignored", key, *text));
  return std::nullopt;
}

glm::vec3 EntityKeys::colour(std::string_view key, glm::vec3 fallback) const {
  const auto c = vec3(key);
  return c ? normalisedColour(*c) : fallback;
}

void EntityKeys::warn(std::string message) const {
  if (!diagnostics_) return;
  diagnostics_->push_back(
      {Severity::Warning, sourcePath_, entity_.line, 0, fmt::format("{}: {}", entity_.classname(), std::move(message))});
}

} // namespace bt::quake
