// Where tests find their inputs: our own maps/ and the shared community data beside the repo.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

namespace bt::test {

// ../shared beside the repository (or $BRUSHTRACE_SHARED_DIR), if it exists.
std::optional<std::filesystem::path> sharedDir();
std::filesystem::path sourceDir(); // the repository root
std::filesystem::path binaryDir(); // the build folder (build/brushtrace lives there)
std::filesystem::path mapsDir();   // the repository's maps/

} // namespace bt::test

// Skips the current test with a message saying what is missing, when ../shared is absent.
#define BT_REQUIRE_SHARED(var)                                                                                                             \
  const auto var##_opt = ::bt::test::sharedDir();                                                                                          \
  if (!var##_opt) GTEST_SKIP() << "shared test data not found (../shared beside the repository)";                                          \
  const std::filesystem::path var = *var##_opt
