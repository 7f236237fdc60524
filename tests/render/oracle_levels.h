// The lit oracle levels (../shared/oracle/lit/) and the .map each was compiled from: what the
// faithful-mode tests hold to the compiler (oracle_test.cpp at luxel centres, oracle_view_test.cpp
// as a user sees it).
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace bt::test {

// Every lit oracle level (oracle_view_test.cpp EveryLitOracleLevelIsListed that none under oracle/lit/ is left out).
inline const char* const kLitLevels[] = {
    "ericw-tools_testmaps_deprecated_falloff",
    "ericw-tools_testmaps_deprecated_nobounce",
    "ericw-tools_testmaps_deprecated_dirttest2",
    "ericw-tools_testmaps_deprecated_bouncecolorscaletest",
    "ericw-tools_testmaps_deprecated_light_near_wall",
    "ericw-tools_testmaps_deprecated_suntest",
    "ericw-tools_testmaps_deprecated_testminlight",
    "ericw-tools_testmaps_deprecated_testlightonface",
    "ericw-tools_testmaps_q1_surflight_minlight",
    "ericw-tools_testmaps_q1_light_bounce_litwater",
    "ericw-tools_testmaps_q1_light_bounce_noshadow",
    "ericw-tools_testmaps_deprecated_dirttest",
    "ericw-tools_testmaps_q1_light_hlform",
    "ericw-tools_testmaps_q1_light_skip_shadow",
    "ericw-tools_testmaps_q1_light_suntexture",
    "ericw-tools_testmaps_q1_light_surflight_group",
    "ericw-tools_testmaps_q1_light_switchableshadow_selfshadows",
    "ericw-tools_testmaps_q1_litwater_opt_in",
    "ericw-tools_testmaps_q1_light_black",
    "ericw-tools_testmaps_q1_lightignore",
    "ericw-tools_testmaps_q1_light_switchableshadow_target",
    "ericw-tools_testmaps_q1_sunlight",
    "ericw-tools_testmaps_q1_litwater",
    "ericw-tools_testmaps_q1_minlight_nobounce",
    "quake_map_source_e1m1",
    "ericw-tools_testmaps_deprecated_testsurfacelight",
    "ericw-tools_testmaps_q1_light_invalid_delay",
    "librequake_lq1_maps_src_dm_lqdm5",
};

// The .map each lit .bsp was compiled from (oracle/manifest.json).
inline std::filesystem::path oracleSourceMap(const std::filesystem::path& shared, const std::string& bspName) {
  std::ifstream in(shared / "oracle" / "manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(in);
  for (const auto& entry : manifest)
    if (entry.value("bsp", "") == bspName) return shared / entry.value("map", "");
  return {};
}

} // namespace bt::test
