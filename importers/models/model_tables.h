// Which model each game's code gives a point entity by its classname: a table per game, each
// entry with the game source it comes from. Only the common classes (items, weapons, ammo,
// monsters); README.md "Entity models" lists what is left out and why.
#pragma once

#include <span>
#include <string_view>

namespace bt::models {

struct ClassModel {
  std::string_view classname;
  std::string_view model; // a path in the game's files
  int spawnflags = 0;     // when not 0: the entry holds only where (spawnflags & this) != 0
  int skin = 0;           // .mdl skin (items.qc's armour colours)
  std::string_view source;
};

// "quake", "quake2", "quake3" (game profile names); empty for the others.
std::span<const ClassModel> classModels(std::string_view game);

// The model a point entity of `classname` shows, or nullptr: the first entry whose spawnflags
// condition holds, as the spawn functions test their flags in order.
const ClassModel* findClassModel(std::string_view game, std::string_view classname, int spawnflags);

} // namespace bt::models
