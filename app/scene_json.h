// The JSON forms of an imported scene that `dump --json` and `info --json` print (schema in README).
#pragma once

#include "scene/scene.h"

#include <nlohmann/json.hpp>

namespace bt::app {

nlohmann::ordered_json dumpJson(const Scene& scene);

} // namespace bt::app
