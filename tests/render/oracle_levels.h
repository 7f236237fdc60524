// The lit oracle levels (../shared/oracle/lit/ and lit-games/) and the .map each was compiled from: what the
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

// Every Quake 2 and Half-Life level of oracle/lit-games/ (games_oracle_view_test.cpp
// EveryLitGameLevelIsListed checks that none is left out).
inline const char* const kLitGameLevels[] = {
    "ericw-tools_testmaps_hl_basic",
    "ericw-tools_testmaps_hl_currents",
    "ericw-tools_testmaps_hl_light_black",
    "ericw-tools_testmaps_light_q2_emissive_cube",
    "ericw-tools_testmaps_light_q2_translucent_shadow",
    "ericw-tools_testmaps_q2_alphatest_solid",
    "ericw-tools_testmaps_q2_alphatest_window",
    "ericw-tools_testmaps_q2_areaportal",
    "ericw-tools_testmaps_q2_areaportal_split",
    "ericw-tools_testmaps_q2_areaportal_with_detail",
    "ericw-tools_testmaps_q2_areaportals",
    "ericw-tools_testmaps_q2_bmodel_collision",
    "ericw-tools_testmaps_q2_chop_order_0",
    "ericw-tools_testmaps_q2_chop_order_1",
    "ericw-tools_testmaps_q2_csg_detail_solid_eats_other_detail",
    "ericw-tools_testmaps_q2_csg_detail_solid_over_structural_water",
    "ericw-tools_testmaps_q2_csg_lava_lava",
    "ericw-tools_testmaps_q2_csg_liquid_combinations",
    "ericw-tools_testmaps_q2_csg_structural_and_detail_zfighting",
    "ericw-tools_testmaps_q2_csg_water_water_current90",
    "ericw-tools_testmaps_q2_cubes",
    "ericw-tools_testmaps_q2_detail",
    "ericw-tools_testmaps_q2_detail_fence",
    "ericw-tools_testmaps_q2_detail_fence_with_detail_bit",
    "ericw-tools_testmaps_q2_detail_leak_test",
    "ericw-tools_testmaps_q2_detail_non_sealing",
    "ericw-tools_testmaps_q2_detail_overlapping_solid_sealing",
    "ericw-tools_testmaps_q2_detail_wall",
    "ericw-tools_testmaps_q2_detail_wall_with_detail_bit",
    "ericw-tools_testmaps_q2_dirt",
    "ericw-tools_testmaps_q2_door",
    "ericw-tools_testmaps_q2_double_areaportal",
    "ericw-tools_testmaps_q2_func_illusionary_visblocker",
    "ericw-tools_testmaps_q2_hdrtest",
    "ericw-tools_testmaps_q2_hint_missing_faces",
    "ericw-tools_testmaps_q2_ladder",
    "ericw-tools_testmaps_q2_lavaclip",
    "ericw-tools_testmaps_q2_lavawater",
    "ericw-tools_testmaps_q2_leaked",
    "ericw-tools_testmaps_q2_light_black",
    "ericw-tools_testmaps_q2_light_cone",
    "ericw-tools_testmaps_q2_light_divzero",
    "ericw-tools_testmaps_q2_light_flush",
    "ericw-tools_testmaps_q2_light_group",
    "ericw-tools_testmaps_q2_light_group_dirt",
    "ericw-tools_testmaps_q2_light_low_luxel_res",
    "ericw-tools_testmaps_q2_light_low_luxel_res2",
    "ericw-tools_testmaps_q2_light_negative",
    "ericw-tools_testmaps_q2_light_negative_bounce",
    "ericw-tools_testmaps_q2_light_origin_brush_shadow",
    "ericw-tools_testmaps_q2_light_sun",
    "ericw-tools_testmaps_q2_light_sun_mangle",
    "ericw-tools_testmaps_q2_light_sunlight_default_mangle",
    "ericw-tools_testmaps_q2_light_translucency",
    "ericw-tools_testmaps_q2_light_visapprox",
    "ericw-tools_testmaps_q2_light_visapprox2",
    "ericw-tools_testmaps_q2_lightmap_custom_scale",
    "ericw-tools_testmaps_q2_liquids",
    "ericw-tools_testmaps_q2_long_texture_name",
    "ericw-tools_testmaps_q2_minlight_inherited",
    "ericw-tools_testmaps_q2_minlight_nomottle",
    "ericw-tools_testmaps_q2_mirrorinside",
    "ericw-tools_testmaps_q2_missing_faces2",
    "ericw-tools_testmaps_q2_missing_faces3",
    "ericw-tools_testmaps_q2_mist_aux_implicitly_detail",
    "ericw-tools_testmaps_q2_mist_clip",
    "ericw-tools_testmaps_q2_mist_transwater",
    "ericw-tools_testmaps_q2_noclipfaces_junction",
    "ericw-tools_testmaps_q2_noclipfaces_nodraw",
    "ericw-tools_testmaps_q2_nodraw_detail_light",
    "ericw-tools_testmaps_q2_nodraw_light",
    "ericw-tools_testmaps_q2_omitdetail_in_func",
    "ericw-tools_testmaps_q2_playerclip",
    "ericw-tools_testmaps_q2_region_origin_leak",
    "ericw-tools_testmaps_q2_seal_empty_rooms",
    "ericw-tools_testmaps_q2_skip",
    "ericw-tools_testmaps_q2_surface_lights_culling",
    "ericw-tools_testmaps_q2_tb_cleanup",
    "ericw-tools_testmaps_q2_tjunc_matrix",
    "ericw-tools_testmaps_q2_trans33_solid",
    "ericw-tools_testmaps_q2_trans33_window",
    "ericw-tools_testmaps_q2_unknown_contents",
    "trenchbroom_lib_TbMdlLib_test_fixture_mdl_LoadBspModel_hl",
    "trenchbroom_lib_TbMdlLib_test_fixture_mdl_Map_lavaAndWater",
};

// The .map each lit .bsp was compiled from (the manifest.json of oracle/ or of `folder`).
inline std::filesystem::path oracleSourceMap(const std::filesystem::path& shared, const std::string& bspName,
                                             const std::string& folder = "") {
  std::ifstream in(shared / "oracle" / folder / "manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(in);
  for (const auto& entry : manifest)
    if (entry.value("bsp", "") == bspName) return shared / entry.value("map", "");
  return {};
}

} // namespace bt::test
