// The checkpoint file (dynamic/protocols/checkpoint.hpp): every value reads back to the same
// bits, and a damaged file is refused with a message naming it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "../common/tiny_samples.hpp"
#include "common/io/configuration_file.hpp"
#include "dynamic/protocols/checkpoint.hpp"

namespace granstab::protocols {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Built by append: GCC 12 reports a false -Wrestrict on value_name(k).
std::string value_name(std::size_t k) {
  std::string name = "v";
  name.append(std::to_string(k));
  return name;
}

TEST(Checkpoint, ValuesReadBackToTheSameBits) {
  const double values[] = {0.1,
                           1.0 / 3.0,
                           -2.5e-310,
                           1e300,
                           -0.0,
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::denorm_min(),
                           0.30000000000000004};
  Checkpoint c;
  for (std::size_t k = 0; k < std::size(values); ++k) {
    c.set_number(value_name(k), values[k]);
  }
  c.set_count("count", 18446744073709551615ull);
  c.set_flag("yes", true);
  c.set("text", "line one\nline two\n\nend 5\n");  // newlines and a fake end line inside
  c.set("empty", "");
  const Checkpoint back = Checkpoint::parse(c.format(), "test");
  for (std::size_t k = 0; k < std::size(values); ++k) {
    EXPECT_TRUE(same_bits(back.number(value_name(k)), values[k])) << k;
  }
  EXPECT_EQ(back.count("count"), 18446744073709551615ull);
  EXPECT_TRUE(back.flag("yes"));
  EXPECT_EQ(back.text("text"), "line one\nline two\n\nend 5\n");
  EXPECT_EQ(back.text("empty"), "");
  EXPECT_EQ(back.format(), c.format());
}

TEST(Checkpoint, ConfigurationAndCursorRoundTrip) {
  Configuration config = samples::square_stack(3, 1e3);
  config.disks.vx[4] = 1.0 / 7.0;
  config.time = 0.1 + 0.2;
  config.step = 12345;
  Cursor cursor;
  cursor.phase = 2;
  cursor.index = 17;
  cursor.steps = 400;
  cursor.done_steps = 99999;
  cursor.next_record = 3e-4;
  cursor.values = {1.0 / 3.0, -1e-17};
  cursor.rng_state = "1 2 3";
  cursor.report.max_net_force = 2.0 / 3.0;
  cursor.report.max_force_disk = 7;
  cursor.report.stress_checked = {true, false};
  Checkpoint c;
  c.set_configuration("engine", config);
  put_cursor(c, cursor);
  const Checkpoint back = Checkpoint::parse(c.format(), "test");
  EXPECT_EQ(format_configuration(back.configuration("engine")), format_configuration(config));
  const Cursor r = get_cursor(back);
  EXPECT_EQ(r.phase, 2);
  EXPECT_EQ(r.index, 17);
  EXPECT_EQ(r.steps, 400u);
  EXPECT_EQ(r.done_steps, 99999u);
  EXPECT_TRUE(same_bits(r.next_record, 3e-4));
  ASSERT_EQ(r.values.size(), 2u);
  EXPECT_TRUE(same_bits(r.values[0], 1.0 / 3.0));
  EXPECT_EQ(r.rng_state, "1 2 3");
  EXPECT_TRUE(same_bits(r.report.max_net_force, 2.0 / 3.0));
  EXPECT_EQ(r.report.max_force_disk, 7u);
  EXPECT_TRUE(r.report.stress_checked[0]);
  EXPECT_FALSE(r.report.stress_checked[1]);
}

TEST(Checkpoint, DamagedFilesAreRefused) {
  Checkpoint c;
  c.set_number("x", 0.5);
  c.set("name", "abc");
  const std::string good = c.format();
  const auto message = [](const std::string& text) {
    try {
      Checkpoint::parse(text, "f.checkpoint");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(good), "accepted");
  // One flipped byte in a value: the checksum no longer matches.
  std::string flipped = good;
  flipped[flipped.find("abc")] = 'x';
  EXPECT_NE(message(flipped).find("f.checkpoint: checksum mismatch"), std::string::npos);
  // Cut anywhere: refused.
  for (std::size_t cut = 0; cut < good.size(); ++cut) {
    EXPECT_NE(message(good.substr(0, cut)), "accepted") << cut;
  }
  EXPECT_NE(message("granstab-checkpoint 2\nend 0\n").find("format version 1"), std::string::npos);
  EXPECT_NE(message(good + "x").find("data after the end line"), std::string::npos);
  const Checkpoint back = Checkpoint::parse(good, "f.checkpoint");
  try {
    (void)back.number("missing");
    ADD_FAILURE() << "a missing entry was read";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "f.checkpoint: entry missing: missing");
  }
  EXPECT_THROW((void)back.number("name"), std::runtime_error);
}

}  // namespace
}  // namespace granstab::protocols
