// The layout that docs/architecture.md section 2 documents. The include order: core <- drivers <- server, and
// inside core/ and server/ the folder orders on the doc's "core:" and "server:" lines. A folder includes only
// itself and the folders before it, so there is no include cycle between folders; this test fails on the
// first include that breaks it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::filesystem::path kSourceDir = STRATA_SOURCE_DIR;

/// The `NAME: a < b < c` line of the architecture doc's include-order block, as a list.
std::vector<std::string> documented_order(const std::string& name) {
  std::ifstream doc(kSourceDir / "docs" / "architecture.md");
  std::string line;
  while (std::getline(doc, line)) {
    if (line.rfind(name + ":", 0) != 0)
      continue;
    std::vector<std::string> order;
    std::stringstream items(line.substr(name.size() + 1));
    std::string item;
    while (std::getline(items, item, '<')) {
      item.erase(0, item.find_first_not_of(' '));
      item.erase(item.find_last_not_of(' ') + 1);
      order.push_back(item);
    }
    return order;
  }
  return {};
}

struct Include {
  std::filesystem::path file;  ///< relative to the source tree
  std::string target;          ///< what it includes, e.g. "server/net/listener.hpp"
};

/// Every `#include "..."` of the project's own headers in the C++ files under `folder`.
std::vector<Include> includes_under(const std::string& folder) {
  static const std::regex kInclude(R"re(^\s*#\s*include\s*"([^"]+)")re");
  std::vector<Include> found;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kSourceDir / folder)) {
    const auto extension = entry.path().extension();
    if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".hpp"))
      continue;
    std::ifstream file(entry.path());
    std::string line;
    std::smatch match;
    while (std::getline(file, line))
      if (std::regex_search(line, match, kInclude))
        found.push_back({std::filesystem::relative(entry.path(), kSourceDir), match[1]});
  }
  return found;
}

/// The first path component, or the second for core/ and server/ ("server/net/x.hpp" -> "net").
std::string component(const std::string& path, int depth) {
  std::stringstream parts(path);
  std::string part;
  for (int i = 0; i <= depth; ++i)
    std::getline(parts, part, '/');
  return part;
}

/// Checks that every include in `folder` (at path depth `depth`) names a layer at or before its own.
void expect_order(const std::string& folder, int depth, const std::vector<std::string>& order,
                  const std::string& scope) {
  const auto rank = [&order](const std::string& layer) {
    return static_cast<int>(std::find(order.begin(), order.end(), layer) - order.begin());
  };
  for (const auto& include : includes_under(folder)) {
    if (include.target.rfind(scope, 0) != 0)
      continue;  // another top-level folder, or a header beside the file
    const std::string from = component(include.file.generic_string(), depth);
    const std::string to = component(include.target, depth);
    ASSERT_LT(rank(from), static_cast<int>(order.size())) << from << " is not in the documented order";
    ASSERT_LT(rank(to), static_cast<int>(order.size())) << to << " is not in the documented order";
    EXPECT_LE(rank(to), rank(from)) << include.file.generic_string() << " includes " << include.target << ": "
                                    << from << " comes before " << to << " in docs/architecture.md";
  }
}

/// The doc's order for `top_folder` names its folders, every one of them.
void expect_every_folder_ordered(const std::string& top_folder) {
  const auto order = documented_order(top_folder);
  EXPECT_GE(order.size(), 8U) << top_folder;
  for (const auto& folder : order)
    EXPECT_TRUE(std::filesystem::is_directory(kSourceDir / top_folder / folder))
        << top_folder << "/" << folder;
  for (const auto& entry : std::filesystem::directory_iterator(kSourceDir / top_folder)) {
    if (entry.is_directory()) {
      EXPECT_NE(std::find(order.begin(), order.end(), entry.path().filename().string()), order.end())
          << entry.path().filename().string() << " is not in docs/architecture.md's " << top_folder
          << " order";
    }
  }
}

TEST(Layering, TheArchitectureDocumentsTheOrder) {
  EXPECT_EQ(documented_order("top"), (std::vector<std::string>{"core", "drivers", "server"}));
  expect_every_folder_ordered("core");
  expect_every_folder_ordered("server");
}

TEST(Layering, CoreDriversServerIncludeOnlyDownwards) {
  const auto top = documented_order("top");
  for (const std::string folder : {"core", "drivers", "server"})
    expect_order(folder, 0, top, "");
}

TEST(Layering, CoreFoldersIncludeOnlyEarlierFolders) {
  expect_order("core", 1, documented_order("core"), "core/");
}

TEST(Layering, ServerFoldersIncludeOnlyEarlierFolders) {
  expect_order("server", 1, documented_order("server"), "server/");
}

TEST(Layering, OnlyTheAppKnowsTheSimulator) {
  // The robot's vocabulary (drivers/robot_sample.hpp, drivers/scan_event.hpp) is every driver's; the
  // simulator itself is one driver among others.
  for (const auto& include : includes_under("server")) {
    if (include.target == "drivers/sim/simulator.hpp") {
      EXPECT_EQ(component(include.file.generic_string(), 1), "app") << include.file.generic_string();
    }
  }
}

TEST(Layering, UnitTestsMirrorTheSourceTree) {
  // tests/unit/core/mls/mls_map_test.cpp tests core/mls/: a newcomer finds a folder's tests by its path.
  const auto unit = kSourceDir / "tests" / "unit";
  for (const auto& entry : std::filesystem::recursive_directory_iterator(unit)) {
    if (!entry.is_regular_file() || entry.path().parent_path() == unit)
      continue;  // tests of the whole tree (this one) sit at the top
    const auto folder = std::filesystem::relative(entry.path().parent_path(), unit);
    EXPECT_TRUE(std::filesystem::is_directory(kSourceDir / folder))
        << "tests/unit/" << folder.generic_string() << " has no source folder " << folder.generic_string();
  }
}

}  // namespace
