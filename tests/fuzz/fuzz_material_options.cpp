// libFuzzer target: the biaxial material options' contract (input_oracles.hpp) on arbitrary bytes.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "input_oracles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string violation = granstab::fuzz::material_options_violation(
      std::string_view(reinterpret_cast<const char*>(data), size));
  if (!violation.empty()) {
    std::fprintf(stderr, "contract violated: %s\n", violation.c_str());
    std::abort();  // libFuzzer keeps the input as a crash artefact
  }
  return 0;
}
