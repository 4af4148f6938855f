// The shipped samples in data/samples/ are exactly what the generator writes, so they can be
// regenerated (data/samples/README.md) and their hand-derived properties hold for the files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/equilibrium.hpp"
#include "common/io/configuration_file.hpp"
#include "tiny_samples.hpp"

namespace granstab {
namespace {

const std::filesystem::path samples_dir = GRANSTAB_SAMPLES_DIR;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The generator uses only correctly rounded operations (+, *, /, sqrt) and the build has no
// floating-point contraction in ISO C++ mode, so the text is reproducible to the last digit.
TEST(TinySamples, ShippedFilesMatchTheGenerator) {
  EXPECT_EQ(slurp(samples_dir / "tiny-triangular-periodic.granstab"),
            format_configuration(samples::triangular_lattice(1e3)));
  EXPECT_EQ(slurp(samples_dir / "tiny-square-walls.granstab"),
            format_configuration(samples::square_stack(3, 1e3)));
}

TEST(TinySamples, ShippedFilesAreInEquilibriumUnderUnitPressure) {
  for (const char* name : {"tiny-triangular-periodic.granstab", "tiny-square-walls.granstab"}) {
    const Configuration c = read_configuration(samples_dir / name);
    const EquilibriumReport r = check_equilibrium(c);
    EXPECT_TRUE(r.in_equilibrium) << name;
    EXPECT_LT(r.stress_error[0], 1e-12) << name;
    EXPECT_LT(r.stress_error[1], 1e-12) << name;
  }
}

}  // namespace
}  // namespace granstab
