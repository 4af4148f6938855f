#include "fd_tangent.hpp"

#include "static/kinematics.hpp"

namespace granstab::statics::testing {

Eigen::MatrixXd finite_difference_tangent(const Network& net, const Eigen::VectorXd& dq, double h,
                                          bool* statuses_unchanged) {
  const int n = net.dofs.size;
  const std::vector<ContactState> base = evaluate_contacts(net, dq);
  Eigen::MatrixXd k(n, n);
  bool same = true;
  for (int col = 0; col < n; ++col) {
    Eigen::VectorXd plus = dq, minus = dq;
    plus[col] += h;
    minus[col] -= h;
    const std::vector<ContactState> sp = evaluate_contacts(net, plus);
    const std::vector<ContactState> sm = evaluate_contacts(net, minus);
    for (std::size_t c = 0; c < base.size(); ++c)
      same = same && sp[c].status == base[c].status && sm[c].status == base[c].status;
    k.col(col) = -(residual(net, plus, sp) - residual(net, minus, sm)) / (2.0 * h);
  }
  if (statuses_unchanged) *statuses_unchanged = same;
  return k;
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace granstab::statics::testing
