// ceres_shim.cpp — thin extern "C" layer over Ceres' C++ Solver API for the fit's linear
// least-squares stages (toolchain.md: the C API exposes no solver options and prints reports).
//
// Solver choice, deliberately: the problem is LINEAR (fixed knots, fixed sample parameters,
// gluing functions taken from the construction), so a single Gauss-Newton step from any start is
// the exact least-squares solution.  Levenberg-Marquardt with an initial trust-region radius of
// 1e16 makes its damping (diag/radius) negligible, so one iteration (max_num_iterations = 1) is
// that step.  A stage holds many independent blocks (one per mesh edge or per patch), so the
// default linear solver is SPARSE_NORMAL_CHOLESKY (SuiteSparse CHOLMOD): its normal matrix is
// block diagonal and one sparse factorisation solves all blocks at once; DENSE_QR (Eigen) is
// offered for single-block problems.  num_threads parallelises Jacobian evaluation; logging
// is silent, since library code never prints.
#include "fit/ceres_shim.h"

#include <ceres/ceres.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace {

// One row  r = sum_j c_j x_j - b  with parameter blocks of size dim (1: one coordinate of
// each unknown; 3: the whole point, Jacobian blocks c_j I_3).
class RowCost : public ceres::CostFunction {
public:
    RowCost(const double *c, int k, const double *b, int dim) : c_(c, c + k), dim_(dim)
    {
        for (int d = 0; d < dim; d++) b_[d] = b[d];
        set_num_residuals(dim);
        for (int j = 0; j < k; j++) mutable_parameter_block_sizes()->push_back(dim);
    }
    bool Evaluate(double const *const *p, double *r, double **J) const override
    {
        for (int d = 0; d < dim_; d++) r[d] = -b_[d];
        for (size_t j = 0; j < c_.size(); j++)
            for (int d = 0; d < dim_; d++) r[d] += c_[j] * p[j][d];
        if (J)
            for (size_t j = 0; j < c_.size(); j++) {
                if (!J[j]) continue;
                for (int e = 0; e < dim_ * dim_; e++) J[j][e] = 0.0;
                for (int d = 0; d < dim_; d++) J[j][d * dim_ + d] = c_[j];
            }
        return true;
    }

private:
    std::vector<double> c_;
    double b_[3];
    int dim_;
};

}  // namespace

/* One Ceres solve of rows [r0, r1) (variables anywhere in x): coordinate d alone (dim 1) or
 * all three coordinates as 3-vectors (dim 3, d = 0). */
static int solve_rows(int r0, int r1, int d, int dim, const int *row_start, const int *col, const double *val,
                      const double *rhs, double *x, int threads, int dense, char *msg, int msglen)
{
    ceres::Problem problem;
    std::vector<double *> blocks;
    int used = 0;
    for (int r = r0; r < r1; r++) {
        int k = row_start[r + 1] - row_start[r];
        if (k == 0) continue;
        blocks.clear();
        for (int e = row_start[r]; e < row_start[r + 1]; e++) blocks.push_back(x + 3 * col[e] + d);
        problem.AddResidualBlock(new RowCost(val + row_start[r], k, rhs + 3 * r + d, dim), nullptr, blocks);
        used++;
    }
    if (!used) return 0;
    ceres::Solver::Options o;
    o.minimizer_type = ceres::TRUST_REGION;
    o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    o.initial_trust_region_radius = 1e16;
    o.max_trust_region_radius = 1e16;
    o.max_num_iterations = 1;
    o.linear_solver_type = dense ? ceres::DENSE_QR : ceres::SPARSE_NORMAL_CHOLESKY;
    o.num_threads = threads > 0 ? threads : 1;
    o.logging_type = ceres::SILENT;
    o.minimizer_progress_to_stdout = false;
    std::string why;
    if (!o.IsValid(&why)) {
        std::snprintf(msg, (size_t)msglen, "ceres options: %s", why.c_str());
        return 1;
    }
    ceres::Solver::Summary s;
    ceres::Solve(o, &problem, &s);
    if (!s.IsSolutionUsable() || s.num_successful_steps < 1) {
        std::snprintf(msg, (size_t)msglen, "ceres: %s", s.message.c_str());
        return 1;
    }
    return 0;
}

extern "C" int q2n_ceres_linear_ls(int nvar, int nrow, const int *row_start, const int *col,
                                   const double *val, const double *rhs, double *x, int threads,
                                   int dense, int nitem, const int *item_row, const int *item_var, char *msg,
                                   int msglen)
{
    if (nvar == 0) return 0;
    if (threads < 1) threads = 1;
    if (!dense) {
        for (int d = 0; d < 3; d++)
            if (solve_rows(0, nrow, d, 1, row_start, col, val, rhs, x, threads, 0, msg, msglen)) return 1;
        return 0;
    }
    /* Independent blocks, one small DENSE_QR problem each, spread over `threads` workers
     * (block i goes to worker i mod threads: the result does not depend on the thread count). */
    std::vector<int> fail((size_t)threads, 0);
    std::vector<std::string> why((size_t)threads);
    auto work = [&](int w) {
        char m[256] = "";
        for (int it = w; it < nitem; it += threads) {
            /* small blocks: one problem over 3-vectors (Ceres' per-problem overhead dominates);
             * larger ones: x, y, z separately (the dense QR dominates, 27x cheaper per coordinate) */
            int small = item_var[it + 1] - item_var[it] <= 8;
            for (int d = 0; d < (small ? 1 : 3); d++)
                if (solve_rows(item_row[it], item_row[it + 1], d, small ? 3 : 1, row_start, col, val, rhs, x, 1, 1, m,
                               (int)sizeof m)) {
                    fail[(size_t)w] = 1;
                    why[(size_t)w] = m;
                    return;
                }
        }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; w++) pool.emplace_back(work, w);
    work(0);
    for (auto &t : pool) t.join();
    for (int w = 0; w < threads; w++)
        if (fail[(size_t)w]) {
            std::snprintf(msg, (size_t)msglen, "%s", why[(size_t)w].c_str());
            return 1;
        }
    return 0;
}
