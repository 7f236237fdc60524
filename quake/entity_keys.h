// Entity key values as the games' tools read them: one number rule, one key lookup, typed
// getters. Every importer and the light model read keys through here.
#pragma once

#include "scene/diagnostics.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bt::quake {

// The number rule, for key values and .map number tokens alike. A number is one whole word in
// C's decimal notation (std::from_chars: "12", "-0.5", ".5", "1e3"), finite, with an optional
// leading '+' (ericw-tools reads with stod/sscanf, which take it). Words are separated by
// spaces, tabs or line breaks (sscanf's whitespace). Where ericw-tools stops at the first
// character that is not part of a number and ignores the rest ("64x" reads 64), brushtrace
// rejects the value: a reader then warns, naming the key, and uses the default, rather than
// guess at what the mapper meant.
std::optional<double> parseNumber(std::string_view word);
// Every word of `text` as a number; nullopt when any word is not one (an empty text gives none).
std::optional<std::vector<double>> parseNumbers(std::string_view text);
// Exactly one number that is finite as a float.
std::optional<float> parseFloat(std::string_view text);
// Exactly one number with an integer value that fits an int ("*12" model names, counts).
std::optional<int> parseInteger(std::string_view text);
// Exactly three numbers (origins, angles, colours).
std::optional<glm::dvec3> parseDvec3(std::string_view text);
std::optional<glm::vec3> parseVec3(std::string_view text);

using KeyValues = std::vector<std::pair<std::string, std::string>>;

// The first value of `key`: an exact match first, else one whose key differs only in case or in
// spaces and tabs around it. ericw-tools compares keys ignoring case and its entity parser drops
// the spaces around them, and maps rely on it (q1_surflight_minlight spells
// "_surface_radiosity " with a trailing space).
const std::string* findKey(const KeyValues& keys, std::string_view key);

// Typed getters over one entity's keys. A value that is present but does not read as the type
// asked for gives the fallback and, when `diagnostics` is given, a warning naming the entity's
// file, line, classname, key and value.
class EntityKeys {
public:
  explicit EntityKeys(const Entity& entity, std::string_view sourcePath = {}, Diagnostics* diagnostics = nullptr)
      : entity_(entity), sourcePath_(sourcePath), diagnostics_(diagnostics) {}

  const std::string* find(std::string_view key) const { return findKey(entity_.keys, key); }
  bool has(std::string_view key) const { return find(key) != nullptr; }
  std::string_view string(std::string_view key, std::string_view fallback = {}) const;
  float number(std::string_view key, float fallback) const;
  // A number truncated toward zero, clamped to +-1e6 first so that 1e30 cannot overflow: the
  // compilers read integer keys (style, spawnflags, _bounce) as numbers too.
  int integer(std::string_view key, int fallback) const;
  std::optional<glm::vec3> vec3(std::string_view key) const;
  // `_color` and friends: 0..255 (Quake) or 0..1 (some editors); returned as 0..1, never negative.
  glm::vec3 colour(std::string_view key, glm::vec3 fallback = glm::vec3(1.0f)) const;

  void warn(std::string message) const;

private:
  const Entity& entity_;
  std::string sourcePath_;
  Diagnostics* diagnostics_;
};

// Integer keys arrive as numbers; clamp before converting so that garbage cannot overflow the cast.
int toInt(double value);

// A colour written 0..255 or 0..1, as 0..1 and never negative.
glm::vec3 normalisedColour(glm::vec3 colour);

} // namespace bt::quake
