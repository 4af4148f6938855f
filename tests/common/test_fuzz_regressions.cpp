// Hostile input (issue #8, docs/reliability.md): every input the fuzzers (tests/fuzz) ever
// crashed on, and the seed corpus, replayed through the same contract the fuzzers check. A
// rejected input must throw the documented exception with a "FILE:LINE" message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "common/run_config.hpp"
#include "input_oracles.hpp"

namespace granstab {
namespace {

namespace fs = std::filesystem;

const fs::path fuzz_dir = GRANSTAB_FUZZ_DIR;

// The files of dir, none if it does not exist (git keeps no empty directory).
std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) files.push_back(entry.path());
  return files;
}

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The message of the std::runtime_error f must throw ("" and a failure otherwise).
template <class F>
std::string runtime_error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::runtime_error";
  return {};
}

// "NAME:" followed by a line number >= 1.
void expect_located(const std::string& message, const std::string& name) {
  ASSERT_TRUE(message.starts_with(name + ":")) << message;
  const char after = message.size() > name.size() + 1 ? message[name.size() + 1] : ' ';
  EXPECT_TRUE(after >= '1' && after <= '9') << message;
}

// Each file of tests/fuzz/regressions/TARGET/ is an input that once crashed fuzz_TARGET.
TEST(FuzzRegressions, CrashInputsAreRejectedCleanly) {
  std::size_t replayed = 0;
  for (const auto& file : files_in(fuzz_dir / "regressions" / "configuration")) {
    SCOPED_TRACE(file.string());
    expect_located(runtime_error_of([&] { read_configuration(file); }), file.string());
    EXPECT_EQ(fuzz::configuration_violation(contents(file)), "");
    ++replayed;
  }
  for (const auto& file : files_in(fuzz_dir / "regressions" / "run_config")) {
    SCOPED_TRACE(file.string());
    expect_located(runtime_error_of([&] { RunConfig::from_file(file); }), file.string());
    EXPECT_EQ(fuzz::run_config_violation(contents(file)), "");
    ++replayed;
  }
  EXPECT_GT(replayed, 0u);
}

TEST(FuzzRegressions, SeedCorpusKeepsTheContract) {
  for (const auto& file : files_in(fuzz_dir / "seeds" / "configuration")) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(read_configuration(file));  // the seeds are valid files
    EXPECT_EQ(fuzz::configuration_violation(contents(file)), "");
  }
  for (const auto& file : files_in(fuzz_dir / "seeds" / "run_config")) {
    SCOPED_TRACE(file.string());
    EXPECT_EQ(fuzz::run_config_violation(contents(file)), "");
  }
  for (const auto& file : files_in(fuzz_dir / "seeds" / "material_options")) {
    SCOPED_TRACE(file.string());
    EXPECT_EQ(fuzz::material_options_violation(contents(file)), "");
  }
}

// toml++ 3.3 reaches __builtin_unreachable on some non-ASCII characters in keys, after tokens
// and after a backslash in a multi-line string (found by fuzz_run_config; common/run_config.cpp
// rejects them first). U+00E9 (e acute) and U+00A7 (section sign) are in the affected range.
TEST(FuzzRegressions, TomlCharactersThatTripTheLibraryAreRejectedWithTheirPlace) {
  const auto error = [](const std::string& toml) {
    return runtime_error_of([&] { RunConfig::from_string(toml, "run.toml"); });
  };
  EXPECT_EQ(error("\"caf\xC3\xA9\" = 1\n"),
            "run.toml:1:5: the character U+00E9 is only supported in string values and comments "
            "here (a bug of the TOML library, toml++ 3.3)");
  EXPECT_TRUE(error("x = 1\n[\"\xC3\xA9\"]\n").starts_with("run.toml:2:3: the character U+00E9"));
  EXPECT_TRUE(
      error("s = \"\"\"\\\n  \xC2\xA7\"\"\"\n").starts_with("run.toml:2:3: the character U+00A7"));
  EXPECT_TRUE(
      error("s = \"\"\"\\\xC2\xA7\"\"\"\n").starts_with("run.toml:1:9: the character U+00A7"));
  EXPECT_TRUE(error("x = 1\xC6\xA0\n").starts_with("run.toml:1:6: the character U+01A0"));
  EXPECT_TRUE(error("x = tru\xC3\xA9\n").starts_with("run.toml:1:8: the character U+00E9"));
  EXPECT_TRUE(
      error("a = { \"\xC3\xA9\" = 1 }\n").starts_with("run.toml:1:8: the character U+00E9"));
}

TEST(FuzzRegressions, OverridesThatTripTheLibraryAreTakenAsBareStrings) {
  RunConfig rc = RunConfig::from_string("", "run.toml", {"x=1\xC6\xA0", "y=\"\xC3\xA9\""});
  EXPECT_EQ(rc.string("x", ""), "1\xC6\xA0");  // not TOML: a bare word, as any other
  EXPECT_EQ(rc.string("y", ""), "\xC3\xA9");   // a TOML string value: read as TOML
}

TEST(FuzzRegressions, NonAsciiTextInStringValuesAndCommentsIsStillRead) {
  RunConfig rc = RunConfig::from_string(
      "# r\xC3\xA9glages\n"
      "name = \"caf\xC3\xA9\"\n"
      "paths = ['/home/jos\xC3\xA9', \"\xC2\xA7\"]\n"
      "note = \"\"\"\xC3\xA9\n\xC3\xA9\\\"\"\"\"\n"
      "\"\xE4\xB8\xAD\" = 1\n",  // U+4E2D in a key is outside the affected ranges
      "run.toml");
  EXPECT_EQ(rc.string("name", ""), "caf\xC3\xA9");
  EXPECT_EQ(rc.string("note", ""), "\xC3\xA9\n\xC3\xA9\"");
  EXPECT_EQ(rc.integer("\xE4\xB8\xAD", 0, 0, 10), 1);
  EXPECT_TRUE(rc.contains("paths"));
}

}  // namespace
}  // namespace granstab
