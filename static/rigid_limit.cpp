// Rigid-limit bound (SPEC §4.5, STATIC.md §S3.6). Steps: frames of the frozen network
// (rigid_network) -> remove what carries no force -> assemble the normalised LP (rigid_lp) -> Ipopt
// -> forces and mechanism. The formulation is derived in docs/static.md ("Rigid-limit bound").
#include "static/rigid_limit.hpp"

#include "static/rigid_lp.hpp"
#include "static/rigid_network.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "IpIpoptApplication.hpp"
#include "IpSolveStatistics.hpp"
#include "IpTNLP.hpp"
#include "common/contact_law.hpp"

namespace granstab::statics {

std::mutex& ipopt_mutex() {
  static std::mutex mutex;
  return mutex;
}

namespace {

using rigid::FrozenNetwork;
using rigid::LinearProgram;
using rigid::RowKind;

// ---------------------------------------------------------------------------------------------
// Ipopt interface: minimise (or maximise) s1 subject to the LP rows, x >= 0.

class RigidLimitTnlp : public Ipopt::TNLP {
 public:
  RigidLimitTnlp(const LinearProgram& lp, double objective_sign) : lp_(lp), sign_(objective_sign) {}

  std::vector<double> x, multipliers;
  double s1 = std::numeric_limits<double>::quiet_NaN();

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = lp_.n_columns();
    m = lp_.n_rows();
    nnz_jac = static_cast<Ipopt::Index>(lp_.val.size());
    nnz_h = 0;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* xl, Ipopt::Number* xu, Ipopt::Index m,
                       Ipopt::Number* gl, Ipopt::Number* gu) override {
    for (Ipopt::Index k = 0; k < n; ++k) {
      xl[k] = 0.0;
      xu[k] = infinity;
    }
    xl[lp_.s1_column()] = -infinity;  // s1 is free: friction can make sigma_1 tensile
    for (Ipopt::Index r = 0; r < m; ++r) gl[r] = gu[r] = lp_.rhs[r];
    return true;
  }
  bool get_starting_point(Ipopt::Index n, bool, Ipopt::Number* x0, bool, Ipopt::Number*,
                          Ipopt::Number*, Ipopt::Index, bool, Ipopt::Number*) override {
    std::fill(x0, x0 + n, 1.0);  // forces of order a P
    return true;
  }
  bool eval_f(Ipopt::Index, const Ipopt::Number* xv, bool, Ipopt::Number& f) override {
    f = sign_ * xv[lp_.s1_column()];
    return true;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number*, bool, Ipopt::Number* g) override {
    std::fill(g, g + n, 0.0);
    g[lp_.s1_column()] = sign_;
    return true;
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* xv, bool, Ipopt::Index m,
              Ipopt::Number* g) override {
    std::fill(g, g + m, 0.0);
    for (std::size_t e = 0; e < lp_.val.size(); ++e) g[lp_.row[e]] += lp_.val[e] * xv[lp_.col[e]];
    return true;
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Index, Ipopt::Index,
                  Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* v) override {
    if (v == nullptr) {
      std::copy(lp_.row.begin(), lp_.row.end(), rows);
      std::copy(lp_.col.begin(), lp_.col.end(), cols);
    } else {
      std::copy(lp_.val.begin(), lp_.val.end(), v);
    }
    return true;
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number, Ipopt::Index,
              const Ipopt::Number*, bool, Ipopt::Index, Ipopt::Index*, Ipopt::Index*,
              Ipopt::Number*) override {
    return true;  // an LP: no Hessian entries, but Ipopt still asks (DEPS.md #4)
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* xv,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index m,
                         const Ipopt::Number*, const Ipopt::Number* lambda, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x.assign(xv, xv + n);
    multipliers.assign(lambda, lambda + m);
    s1 = xv[lp_.s1_column()];
  }

 private:
  static constexpr double infinity = 2e19;  // beyond Ipopt's nlp_*_bound_inf (1e19)
  const LinearProgram& lp_;
  double sign_;
};

std::string status_name(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded:
      return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates:
      return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop:
      return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed:
      return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option:
      return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory:
      return "Insufficient_Memory";
    case Ipopt::Internal_Error:
      return "Internal_Error";
  }
  return "unknown status " + std::to_string(static_cast<int>(s));
}

struct Solve {
  Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;
  int iterations = 0;
  Ipopt::SmartPtr<RigidLimitTnlp> tnlp;
};

Solve solve_once(const LinearProgram& lp, double objective_sign, const RigidLimitOptions& options,
                 bool mehrotra, int max_iterations) {
  Solve out;
  out.tnlp = new RigidLimitTnlp(lp, objective_sign);
  const std::lock_guard<std::mutex> lock(ipopt_mutex());  // DEPS.md #5
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetStringValue("sb", "yes");
  o.SetIntegerValue("print_level", 0);
  o.SetNumericValue("bound_relax_factor", 0.0);  // exact F_N >= 0 and cone edges (DEPS.md #4)
  o.SetStringValue("hessian_constant", "yes");
  o.SetStringValue("jac_c_constant", "yes");
  o.SetStringValue("jac_d_constant", "yes");
  o.SetStringValue("mehrotra_algorithm", mehrotra ? "yes" : "no");
  o.SetNumericValue("tol", options.tolerance);
  o.SetNumericValue("constr_viol_tol", options.tolerance);
  o.SetIntegerValue("max_iter", max_iterations);
  out.status = app->Initialize("");  // "" so no stray ipopt.opt is read
  if (out.status != Ipopt::Solve_Succeeded) return out;
  out.status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(out.tnlp));
  if (Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics(); Ipopt::IsValid(stats))
    out.iterations = stats->IterationCount();
  return out;
}

// Mehrotra's predictor-corrector needs about half the iterations of Ipopt's default on these
// LPs (31 vs 56 on 1800 disks), but on infeasible networks it wanders until max_iter, where the
// default algorithm reports Infeasible_Problem_Detected. So: Mehrotra with a short leash, then
// the default algorithm for anything but a clean success.
Solve solve(const LinearProgram& lp, double objective_sign, const RigidLimitOptions& options) {
  constexpr int mehrotra_iterations = 200;
  Solve fast = solve_once(lp, objective_sign, options, true,
                          std::min(mehrotra_iterations, options.max_iterations));
  if (fast.status == Ipopt::Solve_Succeeded) return fast;
  Solve careful = solve_once(lp, objective_sign, options, false, options.max_iterations);
  careful.iterations += fast.iterations;
  return careful;
}

bool succeeded(Ipopt::ApplicationReturnStatus s) { return s == Ipopt::Solve_Succeeded; }

// ---------------------------------------------------------------------------------------------
// Results.

void fill_forces(const Configuration& config, const LinearProgram& lp, const FrozenNetwork& net,
                 const std::vector<double>& x, double force_scale, RigidLimitResult& out) {
  out.f_n.assign(config.contacts.size(), 0.0);
  out.f_t.assign(config.contacts.size(), 0.0);
  for (int e = 0; e < lp.n_edges; ++e) {
    const int k = lp.edge_contact[e];
    out.f_n[k] += force_scale * x[e];
    out.f_t[k] += force_scale * lp.edge_sign[e] * net.mu[k] * x[e];
  }
}

// Multipliers of the scaled rows are the mechanism in units of a (docs/static.md): u = a y_u,
// theta = y_theta, e = y_e; normalised to e_2 = -1.
void fill_mechanism(const Configuration& config, const LinearProgram& lp,
                    const std::vector<double>& y, RigidLimitResult& out) {
  const std::size_t n = config.disks.size();
  out.mechanism_ux.assign(n, 0.0);
  out.mechanism_uy.assign(n, 0.0);
  out.mechanism_theta.assign(n, 0.0);
  out.mechanism_e.assign(2, 0.0);
  for (int r = 0; r < lp.n_rows(); ++r) {
    const int i = lp.row_index[r];
    switch (lp.row_kind[r]) {
      case RowKind::force_x:
        out.mechanism_ux[i] = lp.length_unit * y[r];
        break;
      case RowKind::force_y:
        out.mechanism_uy[i] = lp.length_unit * y[r];
        break;
      case RowKind::torque:
        out.mechanism_theta[i] = y[r];
        break;
      case RowKind::stress:
        out.mechanism_e[i] = y[r];
        break;
    }
  }
  const double e2 = out.mechanism_e[1];
  if (!(e2 < 0.0)) return;  // degenerate dual: leave the raw multipliers
  for (auto* v : {&out.mechanism_ux, &out.mechanism_uy, &out.mechanism_theta, &out.mechanism_e})
    for (double& value : *v) value /= -e2;
}

// Largest violation of the balance rows by the returned forces, recomputed from the
// configuration (not from the LP matrix) so that it also checks the assembly.
double balance_residual(const Configuration& config, const FrozenNetwork& net,
                        const RigidLimitResult& r, double a, double sigma1, double sigma2) {
  const Contacts& c = config.contacts;
  const Cell& cell = config.cell;
  const std::size_t n = config.disks.size();
  std::vector<double> fx(n, 0.0), fy(n, 0.0), torque(n, 0.0);
  double stress1 = 0.0, stress2 = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const ContactFrame& f = net.frame[k];
    const double gx = r.f_n[k] * f.nx + r.f_t[k] * f.tx, gy = r.f_n[k] * f.ny + r.f_t[k] * f.ty;
    const int i = c.i[k], j = c.j[k];
    fx[i] -= gx;
    fy[i] -= gy;
    torque[i] -= f.a_i * r.f_t[k];
    if (!is_wall(j)) {
      fx[j] += gx;
      fy[j] += gy;
      torque[j] -= f.a_j * r.f_t[k];
      if (cell.periodic()) {
        stress1 += f.lx * gx;
        stress2 += f.ly * gy;
      }
    } else if (j == wall_right) {
      stress1 += cell.length[0] * gx;
    } else if (j == wall_top) {
      stress2 += cell.length[1] * gy;
    }
  }
  // Units: a sigma_1 for forces, a^2 sigma_1 for torques and the A sigma rows.
  const double force_unit = a * sigma1, moment_unit = a * a * sigma1;
  double worst =
      std::max(std::abs(stress1 - cell.area() * sigma1), std::abs(stress2 - cell.area() * sigma2)) /
      moment_unit;
  for (std::size_t i = 0; i < n; ++i) {
    if (!net.disk_active[i]) continue;
    worst = std::max({worst, std::abs(fx[i]) / force_unit, std::abs(fy[i]) / force_unit,
                      std::abs(torque[i]) / moment_unit});
  }
  return worst;
}

RigidLimitResult failure(RigidLimitResult r, std::string status) {
  r.q_max = std::numeric_limits<double>::quiet_NaN();
  r.solved = false;
  r.bounded = false;
  r.status = std::move(status);
  return r;
}

}  // namespace

RigidLimitResult rigid_limit(const Configuration& config, const RigidLimitOptions& options) {
  rigid::check_configuration(config, options);
  const FrozenNetwork net = rigid::build_network(config);
  const LinearProgram lp = rigid::assemble(config, net);

  RigidLimitResult result;
  result.n_disks =
      static_cast<std::size_t>(std::count(net.disk_active.begin(), net.disk_active.end(), 1));
  result.n_contacts = static_cast<std::size_t>(std::count(net.active.begin(), net.active.end(), 1));
  result.in_lp.assign(net.active.begin(), net.active.end());
  if (lp.n_edges == 0)
    return failure(result,
                   "infeasible: no contact network carries stress (no contact with h > 0 "
                   "in a load-bearing cluster)");

  // Smallest sigma_1 at sigma_1 + sigma_2 = 2 P: the direction of largest sigma_2 / sigma_1.
  const Solve lowest = solve(lp, +1.0, options);
  result.iterations = lowest.iterations;
  if (lowest.status == Ipopt::Infeasible_Problem_Detected)
    return failure(result, "infeasible: the network cannot balance any compressive stress");
  if (lowest.status == Ipopt::Not_Enough_Degrees_Of_Freedom)
    return failure(result, "ipopt: Not_Enough_Degrees_Of_Freedom (" + std::to_string(lp.n_rows()) +
                               " balance rows, " + std::to_string(lp.n_columns()) +
                               " force unknowns: a hypostatic network, generically infeasible)");
  if (!succeeded(lowest.status)) return failure(result, "ipopt: " + status_name(lowest.status));
  const double s1_min = lowest.tnlp->s1;

  if (s1_min <= options.unbounded_threshold) {
    // q grows without bound along the ray towards sigma_1 -> 0, provided sigma_1 > 0 is
    // attainable at all: check the largest sigma_1.
    const Solve highest = solve(lp, -1.0, options);
    result.iterations += highest.iterations;
    if (!succeeded(highest.status)) return failure(result, "ipopt: " + status_name(highest.status));
    if (highest.tnlp->s1 <= options.unbounded_threshold)
      return failure(result, "infeasible: the network cannot carry sigma_1 > 0");
    result.q_max = std::numeric_limits<double>::infinity();
    result.solved = true;
    result.bounded = false;
    result.status = "unbounded";
    return result;
  }

  result.q_max = 2.0 / s1_min - 2.0;
  result.solved = true;
  result.bounded = true;
  result.status = "optimal";
  // Rescale the normalised forces (units of a P, sigma_1 = s1_min P) to sigma_1 = options.sigma1.
  fill_forces(config, lp, net, lowest.tnlp->x, lp.length_unit * options.sigma1 / s1_min, result);
  fill_mechanism(config, lp, lowest.tnlp->multipliers, result);
  result.max_residual = balance_residual(config, net, result, lp.length_unit, options.sigma1,
                                         options.sigma1 * (1.0 + result.q_max));
  if (!(result.max_residual <= options.residual_limit)) {
    RigidLimitResult bad =
        failure(result, "inaccurate: balance residual " + std::to_string(result.max_residual) +
                            " exceeds residual_limit");
    for (auto* v : {&bad.f_n, &bad.f_t, &bad.mechanism_ux, &bad.mechanism_uy, &bad.mechanism_theta,
                    &bad.mechanism_e})
      v->clear();
    return bad;
  }
  return result;
}

}  // namespace granstab::statics
