#pragma once
// What a result depends on besides its inputs and options: the granstab version, and the BLAS
// under UMFPACK's and CHOLMOD's dense fronts, which Debian picks at run time (alternatives) and
// which sets their round-off (docs/static.md, "Performance"). Printed by `granstab version` and
// recorded in q1.json.
#include <string>

namespace granstab::cli {

std::string granstab_version();
// The file that provides dgemm_ in this process, resolved past Debian's alternatives link;
// "not loaded" without one.
std::string blas_library();

}  // namespace granstab::cli
