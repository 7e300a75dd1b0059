/// @file test_architecture.cpp
/// Keeps ARCHITECTURE.md true: its registry lists equal the registries compiled into the tools,
/// the keys it names as the shared vocabulary are declared by both simulation tools, every
/// deprecated key of every schema is named in the README, and every concrete path it names exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "mpm/material.hpp"
#include "mpm/scene_setup.hpp"
#include "ssdem/scene_setup.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kRoot = SUITE_SOURCE_DIR;

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The text of the section `## title` (up to the next `## `).
std::string section(const std::string& doc, const std::string& title) {
  const std::string head = "\n## " + title + "\n";
  const auto b = doc.find(head);
  if (b == std::string::npos) return {};
  const auto e = doc.find("\n## ", b + head.size());
  return doc.substr(b + head.size(), e == std::string::npos ? std::string::npos : e - b - head.size());
}

/// Every `code` span of `text`.
std::vector<std::string> code_spans(const std::string& text) {
  std::vector<std::string> out;
  const std::regex re("`([^`]+)`");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1].str());
  return out;
}

/// The names listed on the bullet `- <label>: `a`, `b`` of the Registries section.
std::set<std::string> registry_line(const std::string& label) {
  const std::string reg = section(read_text(kRoot / "ARCHITECTURE.md"), "Registries");
  std::istringstream in(reg);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("- " + label + ":", 0) == 0) {
      const auto v = code_spans(line);
      return {v.begin(), v.end()};
    }
  }
  ADD_FAILURE() << "ARCHITECTURE.md, section Registries: no line '- " << label << ": ...'";
  return {};
}

template <class C>
std::set<std::string> as_set(const C& c) {
  return {c.begin(), c.end()};
}

}  // namespace

TEST(ArchitectureDoc, MaterialStylesMatchTheRegistry) {
  EXPECT_EQ(registry_line("material styles"), as_set(mpmfrag::builtin_materials().names()));
}

TEST(ArchitectureDoc, ContactPartsMatchTheRegistry) {
  EXPECT_EQ(registry_line("contact parts"), as_set(ssdem::builtin_contact_parts().names()));
}

TEST(ArchitectureDoc, PipelinePartsMatchTheRulesFiles) {
  std::set<std::string> parts;
  for (const auto& e : fs::directory_iterator(kRoot / "pipelines"))
    if (e.is_directory() && fs::exists(e.path() / "rules.mk")) parts.insert(e.path().filename().string());
  EXPECT_EQ(registry_line("pipeline parts"), parts);
}

TEST(ArchitectureDoc, SharedVocabularyIsDeclaredByBothSimulationTools) {
  const std::string voc = section(read_text(kRoot / "ARCHITECTURE.md"), "One vocabulary");
  const auto keys = code_spans(voc);
  ASSERT_GE(keys.size(), 5u) << "section 'One vocabulary' lists no keys";
  const common::Schema mpm = mpmfrag::mpm_schema(), nbody = ssdem::ssdem_schema();
  for (const auto& k : keys) {
    EXPECT_NE(mpm.find(k), nullptr) << "mpm-frag does not declare '" << k << "'";
    EXPECT_NE(nbody.find(k), nullptr) << "ssdem-grav does not declare '" << k << "'";
  }
}

TEST(ArchitectureDoc, EveryDeprecatedKeyIsNamedInTheReadme) {
  const std::string readme = read_text(kRoot / "README.md");
  const common::Schema mpm = mpmfrag::mpm_schema(), nbody = ssdem::ssdem_schema();
  std::vector<common::AliasSpec> aliases = mpm.aliases();
  aliases.insert(aliases.end(), nbody.aliases().begin(), nbody.aliases().end());
  ASSERT_FALSE(aliases.empty());
  for (const auto& a : aliases) {
    EXPECT_NE(readme.find("`" + a.old_key + "` →"), std::string::npos) << a.old_key;
    EXPECT_NE(readme.find("`" + a.new_key + "`"), std::string::npos) << a.new_key;
  }
}

TEST(ArchitectureDoc, ConcretePathsExist) {
  const std::string doc = read_text(kRoot / "ARCHITECTURE.md");
  int checked = 0;
  for (const auto& span : code_spans(doc)) {
    // Paths: contain a '/' and a file or folder name; templates (<style>) and globs are skipped.
    if (span.find('/') == std::string::npos || span.find_first_of("<*( ") != std::string::npos) continue;
    if (span.find('.') == std::string::npos && span.back() != '/') continue;  // e.g. "m/s^2"
    EXPECT_TRUE(fs::exists(kRoot / span)) << "ARCHITECTURE.md names '" << span << "', which does not exist";
    ++checked;
  }
  EXPECT_GE(checked, 10);
}
