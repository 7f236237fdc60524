// What each game's own code does with a level's entities, where it differs between the games:
// which brush entities it never draws, and where it puts the player's eye.
#pragma once

#include "scene/scene.h"

#include <string_view>

namespace bt {

// The game a level is for, as far as its entities' meaning goes. A Valve 220 .map is Half-Life's
// when its textures come from WAD3 files; without them it reads as Quake's, which differs only in
// the eye height of its spawn points (the hiding rules below hold for both).
enum class Game { Quake, HalfLife, Quake2, Quake3 };

Game gameOf(const Scene& scene);

// Whether the game code never draws this brush entity's model when the level starts (README,
// "What the engine hides", lists each rule with the function of id's or Valve's game code).
bool gameHidesEntity(const Entity& entity, Game game);

} // namespace bt
