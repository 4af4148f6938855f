// Each dependency of DEPS.md exercised once, so that a broken install or link shows as a failing
// test rather than as a mystery later.
#include <gtest/gtest.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>
#include <Spectra/SymEigsSolver.h>
#include <Spectra/MatOp/DenseSymMatProd.h>
#include <toml++/toml.h>

#include "IpIpoptApplication.hpp"
#include "IpTNLP.hpp"

namespace {

Eigen::SparseMatrix<double> tridiagonal(int n, double diag) {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k) {
    t.emplace_back(k, k, diag);
    if (k + 1 < n) {
      t.emplace_back(k, k + 1, -1.0);
      t.emplace_back(k + 1, k, -1.0);
    }
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// The Hill indicator's test of positive definiteness is a simplicial LL^T: DEPS.md #1 names the
// supernodal one, but with final_ll = 1 the simplicial one stops at a non-positive pivot too.
TEST(Dependencies, CholmodLltDetectsIndefinite) {
  Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>> spd;
  spd.cholmod().print = 0;  // DEPS.md #3: CHOLMOD would otherwise print to stdout
  spd.compute(tridiagonal(50, 2.5));
  ASSERT_EQ(spd.info(), Eigen::Success);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(50);
  Eigen::VectorXd x = spd.solve(b);
  EXPECT_LT((tridiagonal(50, 2.5) * x - b).norm(), 1e-12);

  // Negative definite, and indefinite with 5 negative eigenvalues (1.9 - 2 cos(k pi / 51)).
  for (const double diag : {-2.5, 1.9}) {
    Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>> simplicial;
    simplicial.cholmod().print = 0;
    simplicial.compute(tridiagonal(50, diag));
    EXPECT_EQ(simplicial.info(), Eigen::NumericalIssue) << diag;  // DEPS.md #1, #2
  }
}

TEST(Dependencies, UmfpackSolvesUnsymmetric) {
  Eigen::SparseMatrix<double> a = tridiagonal(40, 3.0);
  a.coeffRef(0, 1) = 0.5;  // unsymmetric
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu(a);
  ASSERT_EQ(lu.info(), Eigen::Success);
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(40, 1.0, 2.0);
  EXPECT_LT((a * lu.solve(b) - b).norm(), 1e-12);
  EXPECT_TRUE(std::isfinite(lu.determinant()));  // the static solver tracks its sign
}

TEST(Dependencies, SpectraSmallestEigenvalue) {
  Eigen::MatrixXd m = Eigen::MatrixXd(tridiagonal(30, 2.0));
  Spectra::DenseSymMatProd<double> op(m);
  Spectra::SymEigsSolver<Spectra::DenseSymMatProd<double>> eigs(op, 1, 10);
  eigs.init();
  eigs.compute(Spectra::SortRule::SmallestAlge, 1000, 1e-12);
  ASSERT_EQ(eigs.info(), Spectra::CompInfo::Successful);
  const double exact = 2.0 - 2.0 * std::cos(M_PI / 31.0);
  EXPECT_NEAR(eigs.eigenvalues()(0), exact, 1e-10);
}

// maximise x subject to x + 2 y <= 4, x - y <= 1, x, y >= 0: optimum x = 2, y = 1.
class TinyLp : public Ipopt::TNLP {
 public:
  double x_opt[2] = {0, 0};
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = 2;
    m = 2;
    nnz_jac = 4;
    nnz_h = 0;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index, Ipopt::Number* xl, Ipopt::Number* xu, Ipopt::Index,
                       Ipopt::Number* gl, Ipopt::Number* gu) override {
    xl[0] = xl[1] = 0.0;
    xu[0] = xu[1] = 1e19;
    gl[0] = gl[1] = -1e19;
    gu[0] = 4.0;
    gu[1] = 1.0;
    return true;
  }
  bool get_starting_point(Ipopt::Index, bool, Ipopt::Number* x, bool, Ipopt::Number*,
                          Ipopt::Number*, Ipopt::Index, bool, Ipopt::Number*) override {
    x[0] = x[1] = 0.5;
    return true;
  }
  bool eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    f = -x[0];
    return true;
  }
  bool eval_grad_f(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number* g) override {
    g[0] = -1.0;
    g[1] = 0.0;
    return true;
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Number* g) override {
    g[0] = x[0] + 2 * x[1];
    g[1] = x[0] - x[1];
    return true;
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Index, Ipopt::Index,
                  Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* v) override {
    if (v == nullptr) {
      rows[0] = 0;
      cols[0] = 0;
      rows[1] = 0;
      cols[1] = 1;
      rows[2] = 1;
      cols[2] = 0;
      rows[3] = 1;
      cols[3] = 1;
    } else {
      v[0] = 1;
      v[1] = 2;
      v[2] = 1;
      v[3] = -1;
    }
    return true;
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number, Ipopt::Index,
              const Ipopt::Number*, bool, Ipopt::Index, Ipopt::Index*, Ipopt::Index*,
              Ipopt::Number*) override {
    return true;  // DEPS.md #4: must succeed even with no Hessian entries
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index, const Ipopt::Number* x,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_opt[0] = x[0];
    x_opt[1] = x[1];
  }
};

TEST(Dependencies, IpoptSolvesLinearProgram) {
  Ipopt::SmartPtr<TinyLp> lp = new TinyLp();
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  ASSERT_EQ(app->Initialize(""), Ipopt::Solve_Succeeded);
  ASSERT_EQ(app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(lp)), Ipopt::Solve_Succeeded);
  EXPECT_NEAR(lp->x_opt[0], 2.0, 1e-6);
  EXPECT_NEAR(lp->x_opt[1], 1.0, 1e-6);
}

TEST(Dependencies, Cli11AndTomlParse) {
  CLI::App app;
  double kappa = 0;
  app.add_option("--kappa", kappa);
  const char* argv[] = {"prog", "--kappa", "1e4"};
  app.parse(3, argv);
  EXPECT_EQ(kappa, 1e4);

  auto table = toml::parse("[material]\nkappa = 1e5\n", std::string_view{"inline.toml"});
  EXPECT_EQ(table["material"]["kappa"].value<double>(), 1e5);
  EXPECT_THROW(toml::parse("kappa = = 1", std::string_view{"bad.toml"}), toml::parse_error);
}

TEST(Dependencies, OpenMpRunsTwoThreads) {
  int threads = 0;
#pragma omp parallel
  {
#pragma omp single
    threads = omp_get_num_threads();
  }
  EXPECT_EQ(threads, 2);  // the test is registered with OMP_NUM_THREADS=2
}

}  // namespace
