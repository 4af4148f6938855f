// The protocol outputs (issue #4): CSV time series, JSON summary, progress line, VTK snapshot.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "common/io/configuration_file.hpp"
#include "common/io/csv_writer.hpp"
#include "common/io/vtk_file.hpp"
#include "common/progress.hpp"
#include "dynamic/protocols/json_summary.hpp"
#include "run_granstab.hpp"

namespace granstab {
namespace {

TEST(CsvWriter, WritesNothingBeforeFlushThenRoundTripsNumbers) {
  testing::Workdir dir("csv");
  CsvWriter csv(dir / "series.csv", {"epsilon_2", "q"});
  csv.row({0.1, 1.0 / 3.0});
  csv.row({-0.0, 1e-300});
  EXPECT_FALSE(std::filesystem::exists(dir / "series.csv"));
  csv.flush();
  const std::string text = testing::slurp(dir / "series.csv");
  EXPECT_EQ(text, "epsilon_2,q\n0.1,0.3333333333333333\n-0,1e-300\n");
  EXPECT_EQ(std::stod("0.3333333333333333"), 1.0 / 3.0);
  EXPECT_EQ(csv.rows(), 2u);
  EXPECT_EQ(dir.files().size(), 1u);  // no temporary file left behind
}

TEST(CsvWriter, RowOfTheWrongWidthIsAnError) {
  testing::Workdir dir("csv-width");
  CsvWriter csv(dir / "series.csv", {"a", "b", "c"});
  EXPECT_THROW(csv.row({1.0, 2.0}), std::invalid_argument);
}

TEST(JsonSummary, NestedObjectsAndNonFiniteNumbers) {
  protocols::JsonObject inner;
  inner.add("x", 1.5).add("ok", true);
  protocols::JsonObject o;
  o.add("name", "a \"quoted\" name")
      .add("inner", inner)
      .add("values", std::vector<double>{1.0, NAN});
  EXPECT_EQ(o.text(),
            "{\n"
            "  \"name\": \"a \\\"quoted\\\" name\",\n"
            "  \"inner\": {\n"
            "    \"x\": 1.5,\n"
            "    \"ok\": true\n"
            "  },\n"
            "  \"values\": [1, null]\n"
            "}");
}

TEST(Progress, LineShowsFractionAndLinearEta) {
  // Half done after 10 s: 10 s left at the same rate.
  const std::string line = Progress::format("biaxial", 0.01, 0.02, 10.0, "q 0.3");
  EXPECT_EQ(line, "biaxial:  50.0% (0.01 / 0.02)  elapsed 10 s  ETA 10 s  q 0.3");
  EXPECT_EQ(Progress::format("prepare", 1200, 0.0, 130.0, ""), "prepare: 1200  elapsed 2 min 10 s");
}

TEST(VtkFile, DisksAsVerticesContactsAsLines) {
  const Configuration c = read_configuration(std::filesystem::path(GRANSTAB_SOURCE_DIR) /
                                             "data/samples/tiny-square-walls.granstab");
  const std::string vtu = format_vtu(c);
  // 9 disks in a 3 x 3 stack between walls: 12 disk-disk + 12 disk-wall contacts.
  EXPECT_NE(vtu.find("<Piece NumberOfPoints=\"57\" NumberOfCells=\"33\">"), std::string::npos);
  for (const char* name : {"radius", "velocity", "spin", "net_force", "f_n", "f_t", "sliding"}) {
    EXPECT_NE(vtu.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  }
  // Cell types: 9 vertices (1) then 24 lines (3).
  std::string types = "1 1 1 1 1 1 1 1 1 ";
  for (int k = 0; k < 24; ++k) types += "3 ";
  EXPECT_NE(vtu.find(types), std::string::npos);
}

}  // namespace
}  // namespace granstab
