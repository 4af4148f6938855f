// Writes the tiny samples of data/samples/ (see data/samples/README.md):
//   make_tiny_samples DIRECTORY
#include <filesystem>
#include <iostream>

#include "common/io/configuration_file.hpp"
#include "tiny_samples.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_tiny_samples DIRECTORY\n";
    return 2;
  }
  try {
    const std::filesystem::path dir = argv[1];
    granstab::write_configuration(granstab::samples::triangular_lattice(1e3),
                                  dir / "tiny-triangular-periodic.granstab");
    granstab::write_configuration(granstab::samples::square_stack(3, 1e3),
                                  dir / "tiny-square-walls.granstab");
  } catch (const std::exception& e) {
    std::cerr << "make_tiny_samples: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
