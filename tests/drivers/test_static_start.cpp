// The start of the static commands (issue #19): the biaxial material options, the refusal of
// corrupted or unbalanced starts (exit code, message naming the disk or contact, no files), and
// --polish. End to end on the built binary, except the K_T rescaling, checked on the function.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "common/material_override.hpp"
#include "common/measurements.hpp"
#include "run_granstab.hpp"

namespace {

namespace fs = std::filesystem;
using granstab::testing::CommandResult;
using granstab::testing::quoted;
using granstab::testing::slurp;
using granstab::testing::spit;
using granstab::testing::Workdir;

const fs::path sample = fs::path(GRANSTAB_SAMPLES_DIR) / "periodic-n100-k1e4.granstab";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}
std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}
// Index of the first data row after the header line starting with `header`.
std::size_t first_row(const std::vector<std::string>& lines, const std::string& header) {
  std::size_t k = 0;
  while (k < lines.size() && lines[k].rfind(header, 0) != 0) ++k;
  ++k;
  while (k < lines.size() && lines[k].rfind('#', 0) == 0) ++k;
  return k;
}
// The sample with disk `moved`'s centre set to disk `onto`'s (x y are a disk row's first fields).
std::string with_disk_moved(int moved, int onto) {
  std::vector<std::string> lines = lines_of(slurp(sample));
  const std::size_t d0 = first_row(lines, "disks ");
  std::istringstream a(lines[d0 + onto]), b(lines[d0 + moved]);
  std::string x, y, rest;
  a >> x >> y;
  std::string bx, by;
  b >> bx >> by;
  std::getline(b, rest);
  lines[d0 + moved] = x + " " + y + rest;
  return join(lines);
}
// The sample with one field of a disk row replaced by a number (field 0: x).
std::string with_disk_shifted(int disk, double dx) {
  std::vector<std::string> lines = lines_of(slurp(sample));
  const std::size_t row = first_row(lines, "disks ") + disk;
  std::istringstream in(lines[row]);
  double x = 0.0;
  std::string rest;
  in >> x;
  std::getline(in, rest);
  std::ostringstream out;
  out.precision(17);
  out << x + dx << rest;
  lines[row] = out.str();
  return join(lines);
}
std::string without_timings(const std::string& json) {
  std::string out;
  for (const std::string& l : lines_of(json))
    if (l.find("seconds") == std::string::npos && l.find("\"sample\"") == std::string::npos)
      out += l + "\n";
  return out;
}

class StaticStart : public ::testing::Test {
 protected:
  // Writes `text` beside the work directory (not among the files a command writes).
  std::string input(const std::string& name, const std::string& text) {
    const fs::path p = dir_.root() / name;
    spit(p, text);
    return quoted(p.string());
  }
  void expect_refused(const CommandResult& r, const std::string& what) {
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_TRUE(dir_.files().empty()) << "a refused start wrote files";
  }
  Workdir dir_{"static-start"};
};

TEST_F(StaticStart, DiskMovedOntoAnotherIsRefusedByEveryStaticCommand) {
  const std::string moved = input("moved.granstab", with_disk_moved(2, 1));
  CommandResult r = dir_.run("info " + moved);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("disks 1 and 2 overlap by"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("but are not in the contact list"), std::string::npos) << r.out;
  expect_refused(dir_.run("q1 " + moved + " --out q"), "disks 1 and 2 overlap by");
  expect_refused(dir_.run("q1 " + moved + " --polish --out q"), "geometry is broken");
  expect_refused(dir_.run("compare " + moved + " --dq 0.01 --out c"), "disks 1 and 2 overlap");
  expect_refused(dir_.run("probe " + moved + " --dq 0.01 --at 0.1 --out p"),
                 "disks 1 and 2 overlap");
}

TEST_F(StaticStart, MissingContactIsRefused) {
  std::vector<std::string> lines = lines_of(slurp(sample));
  const std::size_t c0 = first_row(lines, "contacts ");
  lines.erase(lines.begin() + static_cast<long>(c0));  // contact 0: disks 0 and 52
  for (std::string& l : lines)
    if (l.rfind("contacts ", 0) == 0) l = "contacts 164";
  const std::string file = input("missing.granstab", join(lines));
  expect_refused(dir_.run("q1 " + file + " --out q"), "disks 0 and 52 overlap by");
}

TEST_F(StaticStart, UnbalancedStartIsRefusedUnlessPolished) {
  const std::string file = input("shifted.granstab", with_disk_shifted(0, 1e-6));
  expect_refused(dir_.run("q1 " + file + " --out q"), "not in equilibrium");
  const CommandResult r = dir_.run("q1 " + file + " --polish --max-steps 3 --out q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("polished to equilibrium: disks moved by at most"), std::string::npos)
      << r.err;
  const std::string json = slurp(dir_ / "q/q1.json");
  EXPECT_EQ(json.find("\"start_polish\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"max_displacement\": "), std::string::npos) << json;
}

TEST_F(StaticStart, FrictionBelowAContactsForceRatioIsRefusedUnlessClipped) {
  const std::string file = quoted(sample.string());
  // The sample (mu = 0.15) has contacts at |F_T| / F_N = 0.1466, 0.1476, 0.1481.
  expect_refused(dir_.run("q1 " + file + " --mu 0.146 --out q"), "> mu = 0.146");
  expect_refused(dir_.run("q1 " + file + " --set material.kappa=3 --out q"), "material.kappa");
  expect_refused(dir_.run("q1 " + file + " --set material.mu=abc --out q"), "'abc'");
  const CommandResult r =
      dir_.run("q1 " + file + " --mu 0.146 --clip-to-cone --polish --max-steps 2 --out q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("contacts moved onto the Coulomb cone"), std::string::npos) << r.err;
}

TEST_F(StaticStart, MuOptionEqualsTheEditedFileBitForBit) {
  std::string text = slurp(sample);
  const std::size_t at = text.find("material.mu 0.15\n");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 17, "material.mu 0.5\n");
  const std::string edited = input("edited.granstab", text);
  const std::string args = " --max-steps 60 --quiet --out ";
  ASSERT_EQ(dir_.run("q1 " + quoted(sample.string()) + " --mu 0.5" + args + "a").exit_code, 0);
  ASSERT_EQ(dir_.run("q1 " + edited + args + "b").exit_code, 0);
  EXPECT_EQ(slurp(dir_ / "a/static_curve.csv"), slurp(dir_ / "b/static_curve.csv"));
  EXPECT_EQ(without_timings(slurp(dir_ / "a/q1.json")), without_timings(slurp(dir_ / "b/q1.json")));
  EXPECT_NE(slurp(dir_ / "a/q1.json").find("\"mu\": 0.5"), std::string::npos);
}

TEST_F(StaticStart, ProgressLinesUnlessQuiet) {
  const std::string file = quoted(sample.string());
  CommandResult r = dir_.run("q1 " + file + " --mu 0.5 --out a");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("q1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("attempts"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("s/state"), std::string::npos) << r.err;
  r = dir_.run("q1 " + file + " --mu 0.5 --quiet --max-steps 5 --out b");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

// --kt-ratio keeps the start's forces (delta_t rescaled) and changes the curve below q1.
TEST_F(StaticStart, KtRatioKeepsTheStartForcesAndChangesTheCurve) {
  using namespace granstab;
  const Configuration before = read_configuration(sample.string());
  Configuration after = before;
  MaterialOverrides o;
  o.kt_ratio = 0.5;
  apply_material_overrides(after, o);
  EXPECT_EQ(after.material.k_t, 0.5 * before.material.k_n);
  for (std::size_t c = 0; c < before.contacts.size(); ++c) {
    const double f_before = before.material.k_t * before.contacts.delta_t[c];
    const double f_after = after.material.k_t * after.contacts.delta_t[c];
    EXPECT_NEAR(f_after, f_before, 4e-16 * std::abs(f_before)) << "contact " << c;
  }
  const Measurements m0 = measure(before), m1 = measure(after);
  EXPECT_NEAR(m1.q, m0.q, 1e-12);

  const std::string file = quoted(sample.string());
  // Fixed steps: row k of both curves at the same load k dq.
  const std::string args = " --mu 0.5 --max-steps 100 --steps fixed --quiet --out ";
  ASSERT_EQ(dir_.run("q1 " + file + args + "a").exit_code, 0);
  ASSERT_EQ(dir_.run("q1 " + file + " --kt-ratio 0.5" + args + "b").exit_code, 0);
  const std::vector<std::string> a = lines_of(slurp(dir_ / "a/static_curve.csv"));
  const std::vector<std::string> b = lines_of(slurp(dir_ / "b/static_curve.csv"));
  ASSERT_GT(a.size(), 50u);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a[1].substr(0, a[1].find(',')), b[1].substr(0, b[1].find(',')));  // same first load
  EXPECT_NE(a[80], b[80]);  // a softer tangential spring: other strains at the same q
  EXPECT_NE(slurp(dir_ / "b/q1.json").find("\"kt_ratio\": 0.5"), std::string::npos);
}

}  // namespace
