// The configuration file (issue #2, docs/file-format.md): bit-exact round trip of every field,
// atomic writing, and rejection of malformed input with "FILE:LINE: message".
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "tiny_samples.hpp"

namespace granstab {
namespace {

namespace fs = std::filesystem;
using limits = std::numeric_limits<double>;

// ---------------------------------------------------------------------------- round trip

// Finite doubles over the whole range: random bit patterns (uniform in the exponent, so huge,
// tiny and subnormal values all occur) mixed with the awkward special values.
class AwkwardDoubles {
 public:
  explicit AwkwardDoubles(std::uint64_t seed) : bits_(seed) {}
  double any() {
    const std::uint64_t pick = bits_() % 4;
    if (pick == 0) return special_[bits_() % special_.size()];
    while (true) {
      const double v = std::bit_cast<double>(bits_());
      if (std::isfinite(v)) return v;
    }
  }
  double positive() {
    while (true) {
      const double v = std::abs(any());
      if (v > 0.0) return v;
    }
  }
  double unit() {  // in [0, 1]
    const double v = std::abs(any());
    return v <= 1.0 ? v : 1.0 / v;
  }
  std::uint64_t raw() { return bits_(); }

 private:
  std::mt19937_64 bits_;
  std::vector<double> special_{0.0,
                               -0.0,
                               limits::denorm_min(),
                               -limits::denorm_min(),
                               4.9406564584124654e-324 * 3,
                               2.2250738585072009e-308,  // largest subnormal
                               limits::min(),
                               limits::max(),
                               limits::lowest(),
                               limits::epsilon(),
                               0.1,
                               1.0 / 3.0,
                               -1e300,
                               123456789.125};
};

Configuration random_configuration(Boundary boundary, std::uint64_t seed) {
  AwkwardDoubles r(seed);
  Configuration c;
  c.time = r.any();
  c.step = r.raw();
  std::mt19937_64 rng(seed);
  rng.discard(seed % 1000);
  std::ostringstream state;
  state << rng;
  c.rng_state = state.str();
  c.cell.boundary = boundary;
  c.cell.length = {r.positive(), r.positive()};
  c.cell.length_rate = {r.any(), r.any()};
  c.cell.mass = {r.positive(), r.positive()};
  c.material.k_n = r.positive();
  c.material.k_t = r.positive();
  c.material.mu = std::abs(r.any());
  c.material.zeta = r.unit();
  c.material.mu_wall = std::abs(r.any());
  c.stage.reference_length = {r.positive(), r.positive()};
  c.stage.sigma_ext = {r.any(), r.any()};
  c.stage.control = {static_cast<LengthControl>(r.raw() % 3),
                     static_cast<LengthControl>(r.raw() % 3)};
  c.stage.strain_rate = {r.any(), r.any()};
  c.stage.measure = static_cast<StressMeasure>(r.raw() % 2);
  const int n = 40;
  c.disks.resize(n);
  for (int i = 0; i < n; ++i) {
    // Any finite double scaled into the cell keeps its awkward mantissa and exponent.
    for (int a = 0; a < 2; ++a) {
      auto& pos = a == 0 ? c.disks.x : c.disks.y;
      const double L = c.cell.length[a];
      double v = r.unit() * L;
      if (!(v < L)) v = 0.0;  // periodic positions lie in [0, L)
      pos[i] = (r.raw() % 10 == 0) ? -0.0 : v;
    }
    c.disks.radius[i] = r.positive();
    c.disks.mass[i] = r.positive();
    c.disks.inertia[i] = r.positive();
    c.disks.vx[i] = r.any();
    c.disks.vy[i] = r.any();
    c.disks.omega[i] = r.any();
    c.disks.theta[i] = r.any();
  }
  for (int m = 0; m < 100; ++m) {
    const int i = static_cast<int>(r.raw() % n);
    int j = static_cast<int>(r.raw() % n);
    int k1 = 0, k2 = 0;
    if (boundary == Boundary::walls && m % 3 == 0) {
      j = -1 - static_cast<int>(r.raw() % 4);
    } else if (boundary == Boundary::periodic) {
      k1 = static_cast<std::int32_t>(static_cast<std::uint32_t>(r.raw()));
      k2 =
          m % 7 == 0 ? std::numeric_limits<std::int32_t>::min() : static_cast<int>(r.raw() % 3) - 1;
    }
    if (i == j && k1 == 0 && k2 == 0) j = (i + 1) % n;
    c.contacts.add(i, j, k1, k2, r.any(), static_cast<ContactStatus>(r.raw() % 4));
  }
  return c;
}

::testing::AssertionResult same_bits(double a, double b, const std::string& what) {
  if (std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": " << a << " != " << b;
}

void expect_identical(const Configuration& a, const Configuration& b) {
  EXPECT_TRUE(same_bits(a.time, b.time, "time"));
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.rng_state, b.rng_state);
  EXPECT_EQ(a.cell.boundary, b.cell.boundary);
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(same_bits(a.cell.length[k], b.cell.length[k], "cell.length"));
    EXPECT_TRUE(same_bits(a.cell.length_rate[k], b.cell.length_rate[k], "cell.length_rate"));
    EXPECT_TRUE(same_bits(a.cell.mass[k], b.cell.mass[k], "cell.mass"));
    EXPECT_TRUE(same_bits(a.stage.reference_length[k], b.stage.reference_length[k], "reference"));
    EXPECT_TRUE(same_bits(a.stage.sigma_ext[k], b.stage.sigma_ext[k], "sigma_ext"));
    EXPECT_TRUE(same_bits(a.stage.strain_rate[k], b.stage.strain_rate[k], "strain_rate"));
    EXPECT_EQ(a.stage.control[k], b.stage.control[k]);
  }
  EXPECT_EQ(a.stage.measure, b.stage.measure);
  EXPECT_TRUE(same_bits(a.material.k_n, b.material.k_n, "k_n"));
  EXPECT_TRUE(same_bits(a.material.k_t, b.material.k_t, "k_t"));
  EXPECT_TRUE(same_bits(a.material.mu, b.material.mu, "mu"));
  EXPECT_TRUE(same_bits(a.material.zeta, b.material.zeta, "zeta"));
  EXPECT_TRUE(same_bits(a.material.mu_wall, b.material.mu_wall, "mu_wall"));
  ASSERT_EQ(a.disks.size(), b.disks.size());
  auto fa = const_cast<Disks&>(a.disks).fields();
  auto fb = const_cast<Disks&>(b.disks).fields();
  for (std::size_t f = 0; f < fa.size(); ++f)
    for (std::size_t i = 0; i < a.disks.size(); ++i)
      EXPECT_TRUE(same_bits((*fa[f])[i], (*fb[f])[i], "disk field " + std::to_string(f)));
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t m = 0; m < a.contacts.size(); ++m) {
    EXPECT_EQ(a.contacts.i[m], b.contacts.i[m]);
    EXPECT_EQ(a.contacts.j[m], b.contacts.j[m]);
    EXPECT_EQ(a.contacts.k1[m], b.contacts.k1[m]);
    EXPECT_EQ(a.contacts.k2[m], b.contacts.k2[m]);
    EXPECT_TRUE(same_bits(a.contacts.delta_t[m], b.contacts.delta_t[m], "delta_t"));
    EXPECT_EQ(a.contacts.status[m], b.contacts.status[m]);
  }
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("granstab-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "-" + std::to_string(std::random_device{}()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

TEST(ConfigurationFile, RoundTripIsBitExactForAwkwardValues) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    for (const Boundary b : {Boundary::periodic, Boundary::walls}) {
      const Configuration original = random_configuration(b, seed);
      const Configuration back = parse_configuration(format_configuration(original), "memory");
      expect_identical(original, back);
    }
  }
}

TEST(ConfigurationFile, SpecialValuesRoundTripInEveryKindOfField) {
  for (const double v : {-0.0, limits::denorm_min(), -limits::denorm_min(), 2.2250738585072009e-308,
                         limits::max(), limits::lowest(), 0.1, 1.0 / 3.0, 5e-324 * 12345}) {
    Configuration c = samples::triangular_lattice(1e3);
    c.time = v;
    c.cell.length_rate[1] = v;
    c.stage.sigma_ext[0] = v;
    c.disks.vx[0] = v;
    c.disks.theta[15] = v;
    c.contacts.delta_t[47] = v;
    if (v >= 0.0) c.disks.x[1] = v < c.cell.length[0] ? v : 0.0;  // -0 and subnormal positions
    const Configuration back = parse_configuration(format_configuration(c), "memory");
    expect_identical(c, back);
    EXPECT_EQ(std::signbit(back.time), std::signbit(v));
  }
}

TEST(ConfigurationFile, WritesThroughTheFileSystemAtomically) {
  TempDir dir;
  const fs::path file = dir.path() / "sample.granstab";
  const Configuration first = random_configuration(Boundary::walls, 99);
  write_configuration(first, file);
  expect_identical(first, read_configuration(file));
  const Configuration second = samples::triangular_lattice(1e4);
  write_configuration(second, file);  // replaces the existing file
  expect_identical(second, read_configuration(file));
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1) << "no temporary file may be left behind";
}

TEST(ConfigurationFile, RefusesToWriteWhatCannotBeReadBack) {
  TempDir dir;
  const fs::path file = dir.path() / "bad.granstab";
  Configuration c = samples::triangular_lattice(1e3);
  c.disks.vx[3] = limits::quiet_NaN();
  EXPECT_THROW(write_configuration(c, file), std::invalid_argument);
  c.disks.vx[3] = 0.0;
  c.rng_state = "not a state";
  EXPECT_THROW(write_configuration(c, file), std::invalid_argument);
  // Whatever the reader would reject is refused with the reader's message.
  Configuration outside = samples::triangular_lattice(1e3);
  outside.disks.x[2] = outside.cell.length[0];  // periodic positions lie in [0, L1)
  try {
    write_configuration(outside, file);
    ADD_FAILURE() << "wrote a disk outside the cell";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("disk 2: x = "), std::string::npos) << e.what();
  }
  Configuration dangling = samples::square_stack(3, 1e3);
  dangling.contacts.j[0] = 9;
  EXPECT_THROW(write_configuration(dangling, file), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir.path()));
  EXPECT_THROW(
      write_configuration(samples::triangular_lattice(1e3), dir.path() / "no" / "dir.granstab"),
      std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// ---------------------------------------------------------------------------- malformed input

// A valid periodic file; each case below changes one thing and names the line it must report.
const std::vector<std::string> base_lines = {
    "granstab-configuration 1",                     // 1
    "# two disks touching across the x boundary",   // 2
    "time 0.5",                                     // 3
    "step 7",                                       // 4
    "rng_state",                                    // 5
    "boundary periodic",                            // 6
    "cell.length 4 3",                              // 7
    "cell.length_rate 0 0",                         // 8
    "cell.mass 1 1",                                // 9
    "material.k_n 1000",                            // 10
    "material.k_t 500",                             // 11
    "material.mu 0.5",                              // 12
    "material.zeta 1",                              // 13
    "material.mu_wall 0",                           // 14
    "stage.reference_length 4 3",                   // 15
    "stage.sigma_ext 1 1",                          // 16
    "stage.control stress strain_rate",             // 17
    "stage.strain_rate 0 1e-4",                     // 18
    "stage.measure cauchy",                         // 19
    "disks 2",                                      // 20
    "# x y radius mass inertia vx vy omega theta",  // 21
    "0.3 1.5 0.5 1 0.125 0 0 0 0",                  // 22
    "3.9 1.5 0.5 1 0.125 0 0 0 0",                  // 23
    "contacts 1",                                   // 24
    "# i j k1 k2 delta_t status",                   // 25
    "0 1 -1 0 1e-5 stick",                          // 26
    "end",                                          // 27
};

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}
std::string replaced(int line, const std::string& text) {
  auto lines = base_lines;
  lines.at(line - 1) = text;
  return join(lines);
}
std::string first_lines(int n) {
  return join(std::vector<std::string>(base_lines.begin(), base_lines.begin() + n));
}

// The text must be rejected with a message "base.granstab:LINE: ..." containing `what`.
void expect_rejected(const std::string& text, int line, const std::string& what) {
  const std::string prefix = "base.granstab:" + std::to_string(line) + ": ";
  try {
    parse_configuration(text, "base.granstab");
    ADD_FAILURE() << "accepted; expected " << prefix << "..." << what;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message << "\n  expected: " << what;
  }
}

TEST(ConfigurationFile, BaseTextIsValid) {
  const Configuration c = parse_configuration(join(base_lines), "base.granstab");
  EXPECT_EQ(c.disks.size(), 2u);
  EXPECT_EQ(c.contacts.k1[0], -1);
  EXPECT_EQ(c.stage.control[1], LengthControl::strain_rate);
  EXPECT_DOUBLE_EQ(c.contacts.delta_t[0], 1e-5);
}

TEST(ConfigurationFile, DocumentedExampleIsValid) {
  // The example of docs/file-format.md: the first ``` block after "## Example".
  std::ifstream in(fs::path(GRANSTAB_DOCS_DIR) / "file-format.md");
  std::ostringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const auto example = text.find("## Example");
  ASSERT_NE(example, std::string::npos);
  const auto open = text.find("```\n", example);
  const auto close = text.find("```", open + 4);
  ASSERT_NE(close, std::string::npos);
  const std::string block = text.substr(open + 4, close - open - 4);
  EXPECT_EQ(block, join(base_lines)) << "keep the documented example and base_lines in step";
  const Configuration c = parse_configuration(block, "file-format.md");
  EXPECT_EQ(c.contacts.k1[0], -1);
}

TEST(ConfigurationFile, RejectsTruncatedFiles) {
  expect_rejected(first_lines(22), 22, "unexpected end of file, expected disk 1");
  expect_rejected(first_lines(25), 25, "unexpected end of file, expected contact 0");
  expect_rejected(first_lines(26), 26, "unexpected end of file, expected 'end'");
  expect_rejected(first_lines(12), 12, "expected 'material.zeta'");
  expect_rejected("", 1, "empty file");
  // Cut inside the last line: the keyword no longer reads 'end'.
  std::string cut = join(base_lines);
  cut.resize(cut.size() - 3);
  expect_rejected(cut, 27, "unknown keyword 'e'");
}

TEST(ConfigurationFile, RejectsWrongCounts) {
  expect_rejected(replaced(20, "disks 3"), 24,
                  "found 'contacts' after 2 disk lines, but the file declares 3");
  expect_rejected(replaced(20, "disks 1"), 23, "expected 'contacts', found a data line");
  expect_rejected(replaced(24, "contacts 2"), 27,
                  "found 'end' after 1 contact lines, but the file declares 2");
  expect_rejected(replaced(24, "contacts 0"), 26, "expected 'end', found a data line");
  expect_rejected(replaced(20, "disks -1"), 20, "disks = -1: must be >= 0");
  // A corrupt count fails on the lines, without first allocating for two billion disks.
  expect_rejected(replaced(20, "disks 2000000000"), 24, "found 'contacts' after 2 disk lines");
  expect_rejected(replaced(20, "disks 99999999999999999999"), 20, "integer out of range");
  expect_rejected(replaced(20, "disks 2.5"), 20, "disks: '2.5' is not an integer");
  expect_rejected(replaced(7, "cell.length 4"), 7, "cell.length: expected 2 values, found 1");
  expect_rejected(replaced(22, "0.3 1.5 0.5 1 0.125 0 0 0"), 22,
                  "disk 0: expected 9 values, found 8");
}

TEST(ConfigurationFile, RejectsNonNumericAndNonFiniteValues) {
  expect_rejected(replaced(22, "0.3 abc 0.5 1 0.125 0 0 0 0"), 22,
                  "disk 0 y: 'abc' is not a number");
  expect_rejected(replaced(22, "0.3 1.5 0.5 1 0.125 0 0 0 1.5x"), 22,
                  "disk 0 theta: '1.5x' is not a number");
  expect_rejected(replaced(23, "3.9 1.5 0.5 1 0.125 nan 0 0 0"), 23,
                  "disk 1 vx = nan: must be finite");
  expect_rejected(replaced(23, "3.9 1.5 0.5 1 0.125 0 inf 0 0"), 23,
                  "disk 1 vy = inf: must be finite");
  expect_rejected(replaced(3, "time 1e999"), 3, "time = 1e999: out of the range of a double");
  expect_rejected(replaced(16, "stage.sigma_ext 1 -inf"), 16,
                  "stage.sigma_ext[2] = -inf: must be finite");
  expect_rejected(replaced(26, "0 1 -1 0 0x1p3 stick"), 26,
                  "contact 0 delta_t: '0x1p3' is not a number");
  expect_rejected(replaced(4, "step -7"), 4, "step: '-7' is not an integer");
  expect_rejected(replaced(26, "0 1 99999999999 0 0 stick"), 26,
                  "contact 0 k1 = 99999999999: integer out of range");
}

TEST(ConfigurationFile, RejectsNonPositiveRadiiMassesAndInertia) {
  expect_rejected(replaced(22, "0.3 1.5 -0.5 1 0.125 0 0 0 0"), 22, "disk 0: radius must be > 0");
  expect_rejected(replaced(23, "3.9 1.5 0 1 0.125 0 0 0 0"), 23, "disk 1: radius must be > 0");
  expect_rejected(replaced(23, "3.9 1.5 0.5 -0 0.125 0 0 0 0"), 23, "disk 1: mass must be > 0");
  expect_rejected(replaced(23, "3.9 1.5 0.5 1 0 0 0 0 0"), 23, "disk 1: inertia must be > 0");
}

TEST(ConfigurationFile, RejectsDisksOutsideTheCell) {
  expect_rejected(replaced(23, "4 1.5 0.5 1 0.125 0 0 0 0"), 23,
                  "disk 1: x = 4 is outside the periodic cell [0, 4)");
  expect_rejected(replaced(22, "0.3 -0.001 0.5 1 0.125 0 0 0 0"), 22,
                  "disk 0: y = -0.001 is outside the periodic cell [0, 3)");
  // Walls: the centre must lie in the closed box; image shifts are meaningless.
  auto walls = base_lines;
  walls[5] = "boundary walls";
  walls[25] = "0 1 0 0 0 stick";
  EXPECT_NO_THROW(parse_configuration(join(walls), "base.granstab"));
  auto outside = walls;
  outside[22] = "4.25 1.5 0.5 1 0.125 0 0 0 0";
  expect_rejected(join(outside), 23, "disk 1: x = 4.25 is outside the walls [0, 4]");
  auto shifted = walls;
  shifted[25] = "0 1 -1 0 0 stick";
  expect_rejected(join(shifted), 26, "image shift (-1, 0) must be (0, 0) between walls");
  auto wall_contact = walls;
  wall_contact[25] = "1 right 0 0 0 stick";
  EXPECT_EQ(parse_configuration(join(wall_contact), "w").contacts.j[0], wall_right);
}

TEST(ConfigurationFile, RejectsBadContacts) {
  expect_rejected(replaced(26, "0 2 -1 0 0 stick"), 26, "contact 0: j = 2 out of range [0, 2)");
  expect_rejected(replaced(26, "-1 1 -1 0 0 stick"), 26, "contact 0: i = -1 out of range [0, 2)");
  expect_rejected(replaced(26, "0 -3 -1 0 0 stick"), 26, "contact 0: j = -3 out of range");
  expect_rejected(replaced(26, "0 top 0 0 0 stick"), 26, "wall contact 'top' in a periodic cell");
  expect_rejected(replaced(26, "1 1 0 0 0 stick"), 26, "disk 1 in contact with itself");
  expect_rejected(replaced(26, "0 1 -1 0 0 slide"), 26, "contact 0 status: unknown value 'slide'");
  expect_rejected(replaced(26, "0 1 -1 0 0 stick extra"), 26,
                  "contact 0: trailing garbage 'extra'");
  // A disk may touch its own image across the cell.
  EXPECT_NO_THROW(parse_configuration(replaced(26, "1 1 1 0 0 slide-"), "base.granstab"));
}

TEST(ConfigurationFile, RejectsUnknownVersionsKeywordsAndGarbage) {
  expect_rejected(replaced(1, "granstab-configuration 2"), 1,
                  "unknown format version '2' (this granstab reads version 1)");
  expect_rejected(replaced(1, "granstab-configuration"), 1, "expected 1 values, found 0");
  expect_rejected(replaced(1, "P1 4 4"), 1, "not a granstab configuration");
  expect_rejected(replaced(4, "stepp 7"), 4, "unknown keyword 'stepp' (expected 'step')");
  expect_rejected(replaced(3, "step 7"), 3, "expected 'time', found 'step'");
  expect_rejected(replaced(7, "cell.length 4 3 5"), 7,
                  "cell.length: trailing garbage '5' after 2 values");
  expect_rejected(replaced(6, "boundary torus"), 6,
                  "boundary: unknown value 'torus' (one of periodic, walls)");
  expect_rejected(replaced(17, "stage.control stress strain"), 17,
                  "stage.control[2]: unknown value 'strain'");
  expect_rejected(replaced(5, "rng_state 1 2 3"), 5, "rng_state: not a std::mt19937_64 state");
  auto extra = base_lines;
  extra.push_back("# comments and blank lines may follow 'end'");
  extra.push_back("");
  EXPECT_NO_THROW(parse_configuration(join(extra), "base.granstab"));
  extra.push_back("disks 0");
  expect_rejected(join(extra), 30, "trailing content after 'end': 'disks'");
}

TEST(ConfigurationFile, ValidatesCellAndMaterialAtTheirLines) {
  expect_rejected(replaced(7, "cell.length 0 3"), 7, "cell.L1: must be finite and > 0");
  expect_rejected(replaced(9, "cell.mass 1 -1"), 9, "cell.mass2: must be finite and > 0");
  expect_rejected(replaced(13, "material.zeta 2"), 13, "material.zeta: must lie in [0, 1]");
  expect_rejected(replaced(11, "material.k_t -5"), 11, "material.k_t: must be finite and > 0");
  expect_rejected(replaced(15, "stage.reference_length 4 0"), 15,
                  "stage.reference_length[2] must be > 0");
}

TEST(ConfigurationFile, ReadingNamesTheFile) {
  TempDir dir;
  const fs::path file = dir.path() / "broken.granstab";
  std::ofstream(file) << replaced(23, "3.9 1.5 -0.5 1 0.125 0 0 0 0");
  try {
    read_configuration(file);
    ADD_FAILURE() << "accepted a negative radius";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(file.string() + ":23: disk 1: radius", 0), 0u)
        << e.what();
  }
  EXPECT_THROW(read_configuration(dir.path() / "missing.granstab"), std::runtime_error);
}

}  // namespace
}  // namespace granstab
