#include "perturbation.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "biaxial.hpp"
#include "common/measurements.hpp"

namespace granstab::protocols {
namespace {

constexpr int loaded_phase = 1, released_phase = 2;

std::string generator_state(const std::mt19937_64& rng) {
  std::ostringstream s;
  s << rng;
  return s.str();
}

}  // namespace

void run_perturbations(Engine& engine, const PerturbationOptions& options, std::mt19937_64& rng,
                       Configuration& state,
                       const std::function<bool(const Engine&, const Configuration&,
                                                const PerturbationRecord&)>& on_record,
                       const EquilibrationObserver& observer, const LoopControl& control) {
  if (!(options.f0 > 0.0)) throw std::invalid_argument("perturbation: f0 must be > 0");
  const std::size_t n = engine.size();
  std::vector<double> fx(n), fy(n);
  std::uniform_real_distribution<double> component(-options.f0, options.f0);
  int first = 1;
  if (control.resume) {
    const Cursor& c = control.cursor;
    if (c.values.size() != 7 || c.index < 1 ||
        (c.phase != loaded_phase && c.phase != released_phase)) {
      throw std::invalid_argument("perturbation: not a perturbation cursor");
    }
    first = static_cast<int>(c.index);
    std::istringstream s(c.rng_state);
    s >> rng;
    if (!s) throw std::invalid_argument("perturbation: bad generator state in the cursor");
  }
  for (int draw = first; draw <= options.repetitions; ++draw) {
    const bool resumed = control.resume && draw == first;
    PerturbationRecord record;
    record.draw = draw;
    Cursor cursor = control.cursor;
    cursor.index = draw;
    cursor.rng_state = generator_state(rng);
    if (resumed) {
      const auto& v = control.cursor.values;
      record.epsilon_2_before = v[0];
      record.epsilon_v_before = v[1];
    } else {
      engine.export_to(state);
      const auto before = strains(state);
      record.epsilon_2_before = before[1];
      record.epsilon_v_before = before[2];
    }
    // Fresh draws, x then y for each disk in index order (reproducible from the seed).
    double mean_x = 0.0, mean_y = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      fx[i] = component(rng);
      fy[i] = component(rng);
      mean_x += fx[i];
      mean_y += fy[i];
    }
    // In a periodic cell nothing holds the sample against a net external force: it would
    // accelerate as a whole and never come to rest. Only the fluctuating part is applied there.
    if (engine.cell().periodic()) {
      mean_x /= static_cast<double>(n);
      mean_y /= static_cast<double>(n);
      for (std::size_t i = 0; i < n; ++i) {
        fx[i] -= mean_x;
        fy[i] -= mean_y;
      }
    }
    // Without this guard a sample that flows at the held q would run until the cell collapses.
    const auto guarded = [&](const Engine& e, const Configuration& s, const EquilibriumReport& r) {
      if (observer && !observer(e, s, r)) return false;
      return std::abs(axial_strain(e) - record.epsilon_2_before) <= options.failure_delta_epsilon_2;
    };
    const bool resume_released = resumed && control.cursor.phase == released_phase;
    if (resume_released) {
      const auto& v = control.cursor.values;
      record.delta_epsilon_2 = v[2];
      record.delta_epsilon_v = v[3];
      record.loaded.steps = static_cast<std::uint64_t>(v[4]);
      record.loaded.reached = v[5] != 0.0;
      record.loaded.aborted = v[6] != 0.0;
      record.loaded.report = control.cursor.report;
    } else {
      engine.set_external_forces(fx, fy);
      cursor.phase = loaded_phase;
      cursor.values = {record.epsilon_2_before, record.epsilon_v_before, 0, 0, 0, 0, 0};
      if (resumed) cursor.steps = control.cursor.steps;
      record.loaded = run_to_equilibrium(engine, options.equilibration, state, guarded, fx, fy,
                                         LoopControl{control.hooks, cursor, resumed});
      const auto loaded = strains(state);
      record.delta_epsilon_2 = loaded[1] - record.epsilon_2_before;
      record.delta_epsilon_v = loaded[2] - record.epsilon_v_before;
    }
    if (options.release) {
      // A resumed released wait has an engine without external forces already.
      if (!resume_released) engine.clear_external_forces();
      cursor.phase = released_phase;
      cursor.values = {record.epsilon_2_before,
                       record.epsilon_v_before,
                       record.delta_epsilon_2,
                       record.delta_epsilon_v,
                       static_cast<double>(record.loaded.steps),
                       record.loaded.reached ? 1.0 : 0.0,
                       record.loaded.aborted ? 1.0 : 0.0};
      cursor.report = record.loaded.report;
      cursor.steps = resume_released ? control.cursor.steps : 0;
      record.released = run_to_equilibrium(engine, options.equilibration, state, guarded, {}, {},
                                           LoopControl{control.hooks, cursor, resume_released});
      const auto released = strains(state);
      record.delta_epsilon_2_released = released[1] - record.epsilon_2_before;
      record.delta_epsilon_v_released = released[2] - record.epsilon_v_before;
    }
    const bool go_on = on_record(engine, state, record);
    if (!go_on || !record.loaded.reached || (options.release && !record.released.reached)) break;
  }
  engine.clear_external_forces();
  engine.export_to(state);
}

}  // namespace granstab::protocols
