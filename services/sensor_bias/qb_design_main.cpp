// windfdi-qb-design: solves the quadratic-boundedness LMI (Witczak et al. Theorem 1, eq 19, or the observer
// form) with CSDP, searches alpha in (0, 1), and writes the gain file K = P^-1 U (eq 30) that
// windfdi-sensor-bias loads.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "design_input.hpp"

using namespace windfdi;
using namespace windfdi::sensor_bias;

namespace {

void usage() {
  std::cout
      << "usage: windfdi-qb-design DESIGN.yaml [--out GAINS.yaml] [--alpha A]\n"
         "  Solves the LMI of Witczak et al. (structure: paper, eq 19) or of the bias-augmented observer\n"
         "  (structure: observer) for a fixed alpha (--alpha or 'alpha:' in the file) or searches alpha in\n"
         "  (0, 1); prints alpha, K = P^-1 U, P, the invariant-set size, and writes the gain file.\n"
         "  --zero-gain writes the discretised model with K = 0 and no certificate (paper mode only).\n"
         "  Exit codes: 0 designed, 2 bad input, 3 infeasible.\n";
}

void print_matrix(const char* name, const Eigen::MatrixXd& M) {
  std::cout << name << " =\n";
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    std::cout << "  ";
    for (Eigen::Index j = 0; j < M.cols(); ++j) std::printf("%14.6g", M(i, j));
    std::fflush(stdout);
    std::cout << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, out;
  double alpha = -1.0;
  bool zero_gain = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else if (a == "--zero-gain") {
      zero_gain = true;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--alpha" && i + 1 < argc) {
      char* end = nullptr;
      alpha = std::strtod(argv[++i], &end);
      if (!end || *end || !(alpha > 0.0 && alpha < 1.0)) {
        std::cerr << "windfdi-qb-design: --alpha must be a number in (0, 1)\n";
        return 2;
      }
    } else if (!a.empty() && a[0] != '-' && input.empty()) {
      input = a;
    } else {
      usage();
      return 2;
    }
  }
  if (input.empty()) {
    usage();
    return 2;
  }
  DesignInput in;
  try {
    in = load_design_input_file(input);
  } catch (const ConfigError& e) {
    std::cerr << "windfdi-qb-design: " << e.what() << "\n";
    return 2;
  }
  if (alpha > 0.0) {
    in.fixed_alpha = true;
    in.alpha = alpha;
  }
  if (zero_gain) {
    // Paper mode only: the discretised model with K = 0 and no QB certificate (docs/papers.md, Witczak et
    // al.: K is irrelevant there).
    QbSolution z;
    z.K = Eigen::MatrixXd::Zero(in.problem.A.rows(), in.problem.C.rows());
    z.P = Eigen::MatrixXd::Identity(in.problem.A.rows(), in.problem.A.rows());
    z.state_bound = z.bias_bound = Eigen::VectorXd();
    z.lmi_max_eigenvalue = 1.0;  // not certified
    z.closed_loop_radius = in.problem.A.eigenvalues().cwiseAbs().maxCoeff();
    std::ofstream f(out.empty() ? "/dev/stdout" : out);
    f << gain_file_text(in, z, input + " (--zero-gain: K = 0, not a QB design)");
    return f ? 0 : 2;
  }
  const QbSolution sol = in.fixed_alpha ? qb_solve(in.problem, in.alpha) : qb_design(in.problem, in.search);
  std::cout << "design " << in.name << " ("
            << (in.problem.structure == QbStructure::kPaper ? "paper eq 19" : "observer") << ", "
            << in.problem.A.rows() << " states, " << in.problem.C.rows()
            << " outputs): " << (in.fixed_alpha ? "fixed alpha" : "alpha search") << ", " << sol.solves
            << " SDPs, " << sol.seconds << " s\n";
  if (!sol.feasible) {
    std::cerr << "windfdi-qb-design: INFEASIBLE: " << sol.message << "\n";
    if (in.problem.structure == QbStructure::kPaper)
      std::cerr << "  (necessary condition: alpha < 1 - rho(A)^2 = " << qb_alpha_upper_bound(in.problem)
                << ")\n";
    return 3;
  }
  std::printf(
      "alpha = %.6g\ntrace = %.6g\nmargin = %.3g\nLMI max eigenvalue (Eigen check) = %.3g\n"
      "closed-loop spectral radius = %.8f\n",
      sol.alpha, sol.trace, sol.margin, sol.lmi_max_eigenvalue, sol.closed_loop_radius);
  std::fflush(stdout);
  print_matrix("K", sol.K);
  print_matrix("P", sol.P);
  if (sol.R.size()) print_matrix("R", sol.R);
  print_matrix("state bound sqrt(diag(P^-1))", sol.state_bound.transpose());
  print_matrix("bias-estimation error bound", sol.bias_bound.transpose());
  if (!sol.message.empty()) std::cout << "note: " << sol.message << "\n";
  if (!out.empty()) {
    std::ofstream f(out);
    f << gain_file_text(in, sol, input);
    if (!f) {
      std::cerr << "windfdi-qb-design: cannot write " << out << "\n";
      return 2;
    }
    std::cout << "wrote " << out << "\n";
  }
  return 0;
}
