// Run settings from TOML with command-line overrides: typed getters, ranges, unknown keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "common/run_config.hpp"

namespace granstab {
namespace {

const char* settings = R"(
[material]
mu = 0.5
kappa = 1e4

[biaxial]
gamma = 1e-4
mode = "SRC"
steps = 20
record = true
)";

// Runs f and returns the message of the exception it must throw.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception";
  return {};
}

TEST(RunConfig, TypedGettersWithDefaults) {
  RunConfig rc = RunConfig::from_string(settings, "run.toml");
  EXPECT_DOUBLE_EQ(rc.number("material.mu", 0.3, 0.0, 10.0), 0.5);
  EXPECT_DOUBLE_EQ(rc.number("material.kappa", 1e3, 1.0, 1e9), 1e4);
  EXPECT_DOUBLE_EQ(rc.number("biaxial.gamma", 1e-3, 0.0, 1.0), 1e-4);
  EXPECT_EQ(rc.integer("biaxial.steps", 5, 1, 1000), 20);
  EXPECT_EQ(rc.choice("biaxial.mode", "SIC", {"SRC", "SIC"}), "SRC");
  EXPECT_TRUE(rc.boolean("biaxial.record", false));
  EXPECT_DOUBLE_EQ(rc.number("material.zeta", 0.9, 0.0, 1.0), 0.9);  // absent: default
  EXPECT_EQ(rc.string("output.name", "run"), "run");
  EXPECT_FALSE(rc.path("output.directory").has_value());
  EXPECT_NO_THROW(rc.finish());
}

TEST(RunConfig, IntegersAreAcceptedAsNumbers) {
  RunConfig rc = RunConfig::from_string("[a]\nx = 3\n", "run.toml");
  EXPECT_DOUBLE_EQ(rc.number("a.x", 0.0, 0.0, 10.0), 3.0);
}

TEST(RunConfig, OutOfRangeValuesNameFileAndKey) {
  RunConfig rc = RunConfig::from_string("[biaxial]\ngamma = -1\nsteps = 0\nmu = 2.5\n", "run.toml");
  EXPECT_EQ(error_of([&] { rc.number("biaxial.gamma", 1e-4, 0.0, 1.0); }),
            "run.toml: biaxial.gamma = -1: must be >= 0");
  EXPECT_EQ(error_of([&] { rc.integer("biaxial.steps", 1, 1, 100); }),
            "run.toml: biaxial.steps = 0: must be >= 1");
  EXPECT_EQ(error_of([&] { rc.number("biaxial.mu", 0.5, 0.0, 1.0); }),
            "run.toml: biaxial.mu = 2.5: must be <= 1");
  RunConfig nan = RunConfig::from_string("x = nan\n", "run.toml");
  EXPECT_EQ(error_of([&] { nan.number("x", 0.0, -1.0, 1.0); }),
            "run.toml: x = nan: must be finite");
}

TEST(RunConfig, WrongTypesAreErrors) {
  RunConfig rc = RunConfig::from_string(
      "gamma = \"fast\"\nsteps = 2.5\nrecord = 1\nmode = 3\nchoice = \"XYZ\"\n", "run.toml");
  EXPECT_EQ(error_of([&] { rc.number("gamma", 0.0, 0.0, 1.0); }),
            "run.toml: gamma = \"fast\": must be a number");
  EXPECT_EQ(error_of([&] { rc.integer("steps", 1, 0, 10); }),
            "run.toml: steps = 2.5: must be an integer");
  EXPECT_EQ(error_of([&] { rc.boolean("record", false); }),
            "run.toml: record = 1: must be true or false");
  EXPECT_EQ(error_of([&] { rc.string("mode", "SRC"); }), "run.toml: mode = 3: must be a string");
  EXPECT_EQ(error_of([&] {
              rc.choice("choice", "SRC", {"SRC", "SIC"});
            }),
            "run.toml: choice = \"XYZ\": must be one of SRC, SIC");
  RunConfig table = RunConfig::from_string("biaxial = 3\n", "run.toml");
  EXPECT_EQ(error_of([&] { table.number("biaxial.gamma", 0.0, 0.0, 1.0); }),
            "run.toml: biaxial = 3: must be a table (it holds biaxial.gamma)");
}

TEST(RunConfig, UnknownKeysAreAllNamed) {
  RunConfig rc = RunConfig::from_string(
      settings + std::string("gama = 1\n[extra]\n[output]\nname = \"x\"\n"), "run.toml");
  rc.number("material.mu", 0.3, 0.0, 1.0);
  rc.number("material.kappa", 1e3, 1.0, 1e9);
  rc.number("biaxial.gamma", 1e-3, 0.0, 1.0);
  rc.integer("biaxial.steps", 5, 1, 1000);
  rc.string("output.name", "");
  // Not read: biaxial.mode, biaxial.record, biaxial.gama (a typo), the empty table extra.
  EXPECT_EQ(error_of([&] { rc.finish(); }),
            "run.toml: unknown keys (not used by this command): biaxial.gama, biaxial.mode, "
            "biaxial.record, extra");
}

TEST(RunConfig, CommandLineOverridesApplyOverTheFile) {
  RunConfig rc = RunConfig::from_string(
      settings, "run.toml",
      {"material.mu=0.3", "biaxial.mode = SIC", "new.table.flag=true", "biaxial.steps=40"});
  EXPECT_DOUBLE_EQ(rc.number("material.mu", 0.5, 0.0, 1.0), 0.3);
  EXPECT_EQ(rc.choice("biaxial.mode", "SRC", {"SRC", "SIC"}), "SIC");  // bare word: a string
  EXPECT_TRUE(rc.boolean("new.table.flag", false));
  EXPECT_EQ(rc.integer("biaxial.steps", 1, 1, 100), 40);
  EXPECT_DOUBLE_EQ(rc.number("material.kappa", 1.0, 1.0, 1e9), 1e4);  // untouched

  RunConfig bad = RunConfig::from_string(settings, "run.toml", {"biaxial.gamma=-2"});
  EXPECT_EQ(error_of([&] { bad.number("biaxial.gamma", 0.0, 0.0, 1.0); }),
            "command line (--set biaxial.gamma=...): biaxial.gamma = -2: must be >= 0");
  // An override of a key no getter reads is an unknown key like any other.
  RunConfig typo = RunConfig::from_string("", "run.toml", {"materail.mu=0.3"});
  EXPECT_NE(error_of([&] { typo.finish(); }).find("materail.mu"), std::string::npos);
  EXPECT_NE(
      error_of([&] { RunConfig::from_string("", "run.toml", {"novalue"}); }).find("key=value"),
      std::string::npos);
  EXPECT_NE(error_of([&] {
              RunConfig::from_string("a = 1\n", "run.toml", {"a.b=2"});
            }).find("a is not a table"),
            std::string::npos);
}

TEST(RunConfig, ParseErrorsGiveFileAndLine) {
  const std::string message =
      error_of([] { RunConfig::from_string("[a]\nx = 1\ny = = 2\n", "run.toml"); });
  EXPECT_EQ(message.rfind("run.toml:3:", 0), 0u) << message;
}

TEST(RunConfig, PathsFromTheFileAreRelativeToIt) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("granstab-rc-" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  const fs::path file = dir / "run.toml";
  std::ofstream(file) << "sample = \"samples/a.granstab\"\nabsolute = \"/x/y\"\nempty = \"\"\n";
  RunConfig rc = RunConfig::from_file(file, {"other=b.granstab"});
  EXPECT_EQ(*rc.path("sample"), dir / "samples/a.granstab");
  EXPECT_EQ(*rc.path("absolute"), fs::path("/x/y"));
  EXPECT_EQ(*rc.path("other"), fs::path("b.granstab"));  // command line: as given
  EXPECT_NE(error_of([&] { rc.path("empty"); }).find("must not be empty"), std::string::npos);
  EXPECT_EQ(rc.source_name(), file.string());
  fs::remove_all(dir);
  EXPECT_NE(error_of([&] { RunConfig::from_file(dir / "missing.toml"); }).find("cannot open"),
            std::string::npos);
}

}  // namespace
}  // namespace granstab
