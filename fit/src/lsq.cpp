/* The least-squares shim: the C API of vr/lsq.h implemented on Ceres Solver
 * (Levenberg-Marquardt, dense QR), with our own central finite differences
 * and an SVD covariance that names the parameters the data cannot separate.
 * This is the only C++ in fit/; nothing here lets an exception or a Ceres
 * CHECK reach the C caller, which is why every argument is validated before
 * Ceres sees it. */
#include "vr/lsq.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>

namespace {

/* Below this reciprocal condition number of the column-scaled J^T J the
 * covariance is refused: the same threshold as Ceres' own
 * Covariance::Options::min_reciprocal_condition_number. */
constexpr double kMinReciprocalCondition = 1e-14;
constexpr double kDefaultStep = 1e-6;
/* A parameter that sits near zero gets steps relative to this fraction of
 * its start value (or of 1 when it starts at zero) rather than to its
 * vanishing current value, so the difference quotient never divides by a
 * denormal step. */
constexpr double kStepFloorFraction = 1e-3;

}  // namespace

struct vr_lsq {
  size_t n = 0;
  size_t m = 0;
  vr_lsq_residual_fn fn = nullptr;
  void *user = nullptr;
  bool analytic = false;
  bool forward = false; /* one-sided differences: half the evaluations */
  std::vector<double> lower, upper, step;
  std::vector<char> fixed;
};

namespace {

vr_status fail(vr_error *err, vr_status status, const std::string &message) {
  return vr_error_set(err, status, "%s", message.c_str());
}

/* Turns whatever escaped into a status; called from every catch (...) so
 * that no exception crosses into C. */
vr_status fail_exception(vr_error *err, const char *where) {
  try {
    throw;
  } catch (const std::bad_alloc &) {
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", where);
  } catch (const std::exception &e) {
    return vr_error_set(err, VR_E_NUMERIC, "%s: %s", where, e.what());
  } catch (...) {
    return vr_error_set(err, VR_E_NUMERIC, "%s: unknown C++ exception", where);
  }
}

/* "0", "0 and 3", "0, 2 and 3". */
std::string join_indices(const std::vector<size_t> &idx) {
  std::string s;
  for (size_t k = 0; k < idx.size(); ++k) {
    if (k > 0) s += (k + 1 == idx.size()) ? " and " : ", ";
    s += std::to_string(idx[k]);
  }
  return s;
}

bool all_finite(const double *v, size_t count) {
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/* Residuals and Jacobian of the user's model at one point, analytic or by
 * finite differences.  Shared by the solver (through Ceres' evaluation
 * callback) and by the covariance, so both see the same derivatives. */
class Model {
 public:
  Model(const vr_lsq &p, const double *start)
      : p_(p), held_(p.fixed), xs_(p.n), typical_(p.n) {
    for (size_t j = 0; j < p.n; ++j) typical_[j] = start[j] != 0 ? std::fabs(start[j]) : 1.0;
  }

  long calls() const { return calls_; }

  /* Parameters whose Jacobian columns are not needed (the caller's fixed
   * ones, plus those the solver holds on a bound). */
  void hold(const std::vector<char> &held) { held_ = held; }

  /* f = residuals at x; false if the callback failed or gave a non-finite
   * value. */
  bool residuals(const double *x, double *f) {
    ++calls_;
    if (p_.fn(x, f, nullptr, p_.user) != 0) return false;
    return all_finite(f, p_.m);
  }

  /* J (m x n, row-major) at x, given f0 = residuals at x.  Columns of fixed
   * parameters are left at zero: Ceres' SubsetManifold drops them anyway,
   * and the covariance never reads them, so differencing them would only
   * cost callback calls. */
  bool jacobian(const double *x, const double *f0, double *J) {
    const size_t n = p_.n, m = p_.m;
    if (p_.analytic) {
      std::vector<double> f(m);
      ++calls_;
      if (p_.fn(x, f.data(), J, p_.user) != 0) return false;
      for (size_t j = 0; j < n; ++j)
        if (held_[j])
          for (size_t i = 0; i < m; ++i) J[i * n + j] = 0;
      return all_finite(J, m * n);
    }
    std::fill(J, J + m * n, 0.0);
    std::vector<double> fp(m), fm(m);
    std::copy(x, x + n, xs_.begin());
    for (size_t j = 0; j < n; ++j) {
      if (held_[j]) continue;
      const double xj = x[j], lo = p_.lower[j], hi = p_.upper[j];
      double h = p_.step[j] * std::max(std::fabs(xj), kStepFloorFraction * typical_[j]);
      bool can_fwd = xj + h <= hi, can_bwd = xj - h >= lo;
      /* Closer to a bound than one step: difference away from it.  When the
       * whole interval is narrower than two steps, shrink the step to the
       * wider side so the callback is never asked outside the bounds. */
      if (!can_fwd && !can_bwd) {
        if (hi - xj >= xj - lo) {
          h = hi - xj;
          can_fwd = h > 0;
        } else {
          h = xj - lo;
          can_bwd = h > 0;
        }
      }
      /* The steps actually taken, after rounding of x +- h. */
      double hf = 0, hb = 0;
      bool ok_f = false, ok_b = false;
      if (can_fwd) {
        xs_[j] = xj + h;
        hf = xs_[j] - xj;
        ok_f = hf > 0 && residuals(xs_.data(), fp.data());
      }
      if (can_bwd && !(p_.forward && ok_f)) {
        xs_[j] = xj - h;
        hb = xj - xs_[j];
        ok_b = hb > 0 && residuals(xs_.data(), fm.data());
      }
      xs_[j] = xj;
      /* A side where the model is undefined (the callback failed) falls
       * back to the one-sided difference on the other side. */
      if (ok_f && ok_b) {
        for (size_t i = 0; i < m; ++i) J[i * n + j] = (fp[i] - fm[i]) / (hf + hb);
      } else if (ok_f) {
        for (size_t i = 0; i < m; ++i) J[i * n + j] = (fp[i] - f0[i]) / hf;
      } else if (ok_b) {
        for (size_t i = 0; i < m; ++i) J[i * n + j] = (f0[i] - fm[i]) / hb;
      } else {
        return false;
      }
    }
    return all_finite(J, m * n);
  }

 private:
  const vr_lsq &p_;
  std::vector<char> held_;
  std::vector<double> xs_;       /* scratch point for the differences */
  std::vector<double> typical_;  /* scale of each parameter, from the start */
  long calls_ = 0;
};

/* Ceres applies the loss to the squared norm of a whole residual block, so
 * the robust losses of vr/lsq.h (one rho per residual) need one block per
 * residual.  The user's callback computes all m residuals at once, so it is
 * called once per point from PrepareForEvaluation and every block copies its
 * row out of this cache. */
class SharedEvaluation final : public ceres::EvaluationCallback {
 public:
  SharedEvaluation(Model &model, const vr_lsq &p, double *x)
      : model_(model), n_(p.n), x_(x), xe_(p.n), f_(p.m), J_(p.m * p.n) {}

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    try {
      if (new_evaluation_point || !have_f_) {
        std::copy(x_, x_ + n_, xe_.begin());
        have_f_ = true;
        f_ok_ = model_.residuals(xe_.data(), f_.data());
        have_J_ = false;
      }
      if (evaluate_jacobians && !have_J_ && f_ok_) {
        have_J_ = true;
        J_ok_ = model_.jacobian(xe_.data(), f_.data(), J_.data());
      }
    } catch (...) {
      /* Evaluate() then reports the point as failed. */
      have_f_ = true;
      f_ok_ = false;
      have_J_ = false;
    }
  }

  /* Row i for one residual block; false makes Ceres treat the point as
   * outside the domain and shrink the trust region. */
  bool row(size_t i, const double *x, double *residual, double *jacobian_row) const {
    if (!f_ok_) return false;
    /* Ceres promises the parameters were announced through
     * PrepareForEvaluation; if that ever stops holding we want to know,
     * not silently fit stale residuals. */
    if (std::memcmp(x, xe_.data(), n_ * sizeof(double)) != 0) {
      stale_ = true;
      return false;
    }
    *residual = f_[i];
    if (jacobian_row) {
      if (!have_J_ || !J_ok_) return false;
      std::copy(&J_[i * n_], &J_[i * n_] + n_, jacobian_row);
    }
    return true;
  }

  bool stale() const { return stale_; }

 private:
  Model &model_;
  size_t n_;
  double *x_;              /* the parameter block Ceres updates */
  std::vector<double> xe_; /* the point the cache belongs to */
  std::vector<double> f_, J_;
  bool have_f_ = false, f_ok_ = false, have_J_ = false, J_ok_ = false;
  mutable std::atomic<bool> stale_{false};
};

class RowCost final : public ceres::CostFunction {
 public:
  RowCost(const SharedEvaluation &shared, size_t row, int n) : shared_(shared), row_(row) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(n);
  }

  bool Evaluate(double const *const *parameters, double *residuals,
                double **jacobians) const override {
    return shared_.row(row_, parameters[0], residuals, jacobians ? jacobians[0] : nullptr);
  }

 private:
  const SharedEvaluation &shared_;
  size_t row_;
};

std::unique_ptr<ceres::LossFunction> make_loss(vr_lsq_loss loss, double a) {
  switch (loss) {
    case VR_LOSS_HUBER: return std::make_unique<ceres::HuberLoss>(a);
    case VR_LOSS_SOFT_L1: return std::make_unique<ceres::SoftLOneLoss>(a);
    case VR_LOSS_CAUCHY: return std::make_unique<ceres::CauchyLoss>(a);
    case VR_LOSS_NONE: break;
  }
  return nullptr;
}

vr_status check_options(const vr_lsq_options &o, vr_error *err) {
  if (o.max_iterations < 0)
    return vr_error_set(err, VR_E_ARG, "max_iterations must be >= 0 (got %d)", o.max_iterations);
  if (!(o.function_tolerance >= 0) || !(o.gradient_tolerance >= 0) ||
      !(o.parameter_tolerance >= 0))
    return vr_error_set(err, VR_E_ARG, "tolerances must be >= 0 (got function %g, gradient %g, "
                        "parameter %g)", o.function_tolerance, o.gradient_tolerance,
                        o.parameter_tolerance);
  if (o.loss != VR_LOSS_NONE && o.loss != VR_LOSS_HUBER && o.loss != VR_LOSS_SOFT_L1 &&
      o.loss != VR_LOSS_CAUCHY)
    return vr_error_set(err, VR_E_ARG, "unknown loss %d", (int)o.loss);
  if (o.loss != VR_LOSS_NONE && !(o.loss_scale > 0 && std::isfinite(o.loss_scale)))
    return vr_error_set(err, VR_E_ARG, "loss_scale must be positive and finite (got %g)",
                        o.loss_scale);
  if (o.num_threads < 1)
    return vr_error_set(err, VR_E_ARG, "num_threads must be >= 1 (got %d)", o.num_threads);
  return VR_OK;
}

/* Start values: finite and inside the bounds, every parameter (fixed ones
 * too, since a fixed value outside its bounds is a caller mistake). */
vr_status check_point(const vr_lsq &p, const double *x, const char *what, vr_error *err) {
  for (size_t j = 0; j < p.n; ++j) {
    if (!std::isfinite(x[j]))
      return vr_error_set(err, VR_E_ARG, "parameter %zu: %s value %g is not finite", j, what,
                          x[j]);
    if (x[j] < p.lower[j] || x[j] > p.upper[j])
      return vr_error_set(err, VR_E_ARG, "parameter %zu: %s value %.17g is outside its bounds "
                          "[%g, %g]", j, what, x[j], p.lower[j], p.upper[j]);
  }
  return VR_OK;
}

/* Ceres logs a warning to stderr (and carries on with fewer) when asked for
 * more threads than its threading model has; a library must not print, so
 * ask for no more than that. */
int ceres_threads(int requested) {
#if defined(CERES_NO_THREADS)
  (void)requested;
  return 1;
#else
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? requested : std::min(requested, (int)std::min(hw, 1024u));
#endif
}

int clamp_int(long v) { return (int)std::min<long>(v, std::numeric_limits<int>::max()); }

size_t count_free(const vr_lsq &p) {
  return (size_t)std::count(p.fixed.begin(), p.fixed.end(), 0);
}

void summary_message(vr_lsq_summary *s, const char *text) {
  if (s) std::snprintf(s->message, sizeof s->message, "%s", text);
}

/* One Ceres run from x, holding the parameters flagged in held.  Ceres
 * writes trial points into its parameter block, so it works on a copy and x
 * only takes the result when Ceres has a usable one. */
void run_ceres(const vr_lsq &p, Model &model, const std::vector<char> &held,
               const ceres::Solver::Options &so, ceres::LossFunction *loss,
               std::vector<double> &x, ceres::Solver::Summary &cs, bool &stale) {
  const int n = (int)p.n;
  std::vector<double> work(x);
  model.hold(held);
  SharedEvaluation shared(model, p, work.data());
  /* Declared before the problem, which only borrows them. */
  std::unique_ptr<ceres::Manifold> subset;
  std::vector<std::unique_ptr<RowCost>> rows;
  ceres::Problem::Options popt;
  popt.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popt.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popt.evaluation_callback = &shared;
  ceres::Problem problem(popt);
  problem.AddParameterBlock(work.data(), n);
  std::vector<int> constant;
  for (size_t j = 0; j < p.n; ++j)
    if (held[j]) constant.push_back((int)j);
  if (!constant.empty()) {
    subset = std::make_unique<ceres::SubsetManifold>(n, constant);
    problem.SetManifold(work.data(), subset.get());
  }
  for (size_t j = 0; j < p.n; ++j) {
    if (held[j]) continue;
    if (std::isfinite(p.lower[j])) problem.SetParameterLowerBound(work.data(), (int)j, p.lower[j]);
    if (std::isfinite(p.upper[j])) problem.SetParameterUpperBound(work.data(), (int)j, p.upper[j]);
  }
  rows.reserve(p.m);
  for (size_t i = 0; i < p.m; ++i) {
    rows.push_back(std::make_unique<RowCost>(shared, i, n));
    problem.AddResidualBlock(rows.back().get(), loss, work.data());
  }
  ceres::Solve(so, &problem, &cs);
  stale = shared.stale();
  if (!stale && (cs.termination_type == ceres::CONVERGENCE ||
                 cs.termination_type == ceres::NO_CONVERGENCE ||
                 cs.termination_type == ceres::USER_SUCCESS))
    x = work;
}

/* Gradient of the (robust) cost 1/2 sum rho(f_i^2) at x, for the free
 * parameters. */
bool cost_gradient(const vr_lsq &p, Model &model, const ceres::LossFunction *loss,
                   const double *x, std::vector<double> &g) {
  std::vector<double> f(p.m), J(p.m * p.n);
  model.hold(p.fixed);
  if (!model.residuals(x, f.data()) || !model.jacobian(x, f.data(), J.data())) return false;
  g.assign(p.n, 0.0);
  for (size_t i = 0; i < p.m; ++i) {
    double rho[3] = {f[i] * f[i], 1, 0};
    if (loss) loss->Evaluate(f[i] * f[i], rho);
    for (size_t j = 0; j < p.n; ++j) g[j] += rho[1] * f[i] * J[i * p.n + j];
  }
  return true;
}

vr_status solve(vr_lsq *p, double *params, const vr_lsq_options *options,
                vr_lsq_summary *summary, vr_error *err) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  vr_lsq_summary local{};
  vr_lsq_summary *s = summary ? summary : &local;
  *s = vr_lsq_summary{};
  s->termination = VR_LSQ_FAILURE;

  if (!p || !params) {
    summary_message(s, "invalid arguments");
    return vr_error_set(err, VR_E_ARG, "vr_lsq_solve: %s is NULL", p ? "params" : "problem");
  }
  const vr_lsq_options o = options ? *options : vr_lsq_default_options();
  vr_status st = check_options(o, err);
  if (st == VR_OK) st = check_point(*p, params, "start", err);
  const size_t nfree = count_free(*p);
  s->free_parameters = nfree;
  if (st == VR_OK && p->m < nfree)
    st = vr_error_set(err, VR_E_ARG, "%zu residuals cannot determine %zu free parameters "
                      "(need at least as many residuals as free parameters)", p->m, nfree);
  if (st != VR_OK) {
    summary_message(s, "invalid arguments");
    return st;
  }

  Model model(*p, params);
  std::vector<double> f(p->m);
  auto finish = [&] {
    s->residual_evaluations = clamp_int(model.calls());
    s->seconds = elapsed();
  };
  /* Checking the start here gives a message about the caller's values
   * instead of Ceres' generic "initial evaluation failed". */
  if (!model.residuals(params, f.data())) {
    finish();
    summary_message(s, "the residual callback failed at the start values");
    return vr_error_set(err, VR_E_ARG, "the residual callback failed (or gave a non-finite "
                        "residual) at the start values");
  }

  std::unique_ptr<ceres::LossFunction> loss = make_loss(o.loss, o.loss_scale);
  auto loss_cost = [&](const std::vector<double> &r) {
    double cost = 0;
    for (double v : r) {
      double rho[3] = {v * v, 1, 0};
      if (loss) loss->Evaluate(v * v, rho);
      cost += 0.5 * rho[0];
    }
    return cost;
  };
  std::vector<double> x(params, params + p->n);
  s->initial_cost = s->final_cost = loss_cost(f);
  s->termination = VR_LSQ_CONVERGED;
  std::string message = "every parameter is fixed; nothing to solve";

  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.function_tolerance = o.function_tolerance;
  so.gradient_tolerance = o.gradient_tolerance;
  so.parameter_tolerance = o.parameter_tolerance;
  so.num_threads = ceres_threads(o.num_threads);
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;

  /* Ceres meets a bound by projecting its unconstrained step onto the box
   * (ceres-solver issue #187).  Once a parameter presses on its bound the
   * projected steps shrink to nothing and the solver stops on the
   * parameter tolerance with the other parameters still far from their
   * optimum.  So: solve, hold every parameter that sits on a bound with the
   * cost gradient pushing outwards, solve the others again, release any
   * held one the gradient now pulls inwards, until the held set settles
   * (a small active-set loop; at most n + 1 rounds). */
  std::vector<char> active(p->n, 0);
  int iterations_left = o.max_iterations;
  for (size_t round = 0; nfree > 0 && round <= p->n; ++round) {
    std::vector<char> held(p->n);
    for (size_t j = 0; j < p->n; ++j) held[j] = p->fixed[j] || active[j];
    if ((size_t)std::count(held.begin(), held.end(), 1) == p->n) {
      message = "every free parameter is held on one of its bounds";
      break;
    }
    so.max_num_iterations = iterations_left;
    std::string why;
    if (!so.IsValid(&why)) {
      finish();
      s->termination = VR_LSQ_FAILURE;
      summary_message(s, why.c_str());
      return fail(err, VR_E_ARG, "invalid solver options: " + why);
    }
    ceres::Solver::Summary cs;
    bool stale = false;
    run_ceres(*p, model, held, so, loss.get(), x, cs, stale);
    /* Ceres records iteration 0 (the start) too. */
    if (!cs.iterations.empty()) s->iterations += (int)cs.iterations.size() - 1;
    iterations_left = std::max(0, o.max_iterations - s->iterations);
    if (round == 0) s->initial_cost = cs.initial_cost;
    s->final_cost = cs.final_cost;
    message = cs.message;
    if (stale) {
      finish();
      s->termination = VR_LSQ_FAILURE;
      summary_message(s, "internal error");
      return vr_error_set(err, VR_E_NUMERIC, "internal error: Ceres evaluated a point it had "
                          "not announced to the evaluation callback");
    }
    if (cs.termination_type == ceres::NO_CONVERGENCE) {
      s->termination = VR_LSQ_NO_CONVERGENCE;
      break;
    }
    if (cs.termination_type != ceres::CONVERGENCE && cs.termination_type != ceres::USER_SUCCESS) {
      finish();
      s->termination = VR_LSQ_FAILURE;
      summary_message(s, message.c_str());
      return fail(err, VR_E_NUMERIC, "the least-squares solver failed: " + message);
    }
    bool on_bound = false;
    for (size_t j = 0; j < p->n; ++j)
      if (!p->fixed[j] && (x[j] == p->lower[j] || x[j] == p->upper[j])) on_bound = true;
    if (!on_bound) break;
    std::vector<double> g;
    if (!cost_gradient(*p, model, loss.get(), x.data(), g)) break;
    std::vector<char> next(p->n, 0);
    for (size_t j = 0; j < p->n; ++j)
      if (!p->fixed[j])
        next[j] = (x[j] == p->lower[j] && g[j] > 0) || (x[j] == p->upper[j] && g[j] < 0);
    if (next == active || round == p->n) break;
    active = next;
  }

  /* chi2 without the loss, at the point we hand back; the callback is asked
   * once more because Ceres' cost includes the loss. */
  const bool ok = model.residuals(x.data(), f.data());
  finish();
  std::vector<size_t> on_bounds;
  for (size_t j = 0; j < p->n; ++j)
    if (active[j]) on_bounds.push_back(j);
  if (!on_bounds.empty())
    message += (on_bounds.size() == 1 ? " (held on its bound: parameter " :
                                        " (held on their bounds: parameters ") +
               join_indices(on_bounds) + ")";
  summary_message(s, message.c_str());
  if (!ok) {
    s->termination = VR_LSQ_FAILURE;
    return vr_error_set(err, VR_E_NUMERIC, "the residual callback failed at the solution it "
                        "had accepted before");
  }
  double chi2 = 0;
  for (double r : f) chi2 += r * r;
  s->chi2 = chi2;
  std::copy(x.begin(), x.end(), params);
  return VR_OK;
}

vr_status covariance(vr_lsq *p, const double *params, bool scale, double *cov, vr_error *err) {
  if (!p || !params || !cov)
    return vr_error_set(err, VR_E_ARG, "vr_lsq_covariance: %s is NULL",
                        !p ? "problem" : !params ? "params" : "covariance");
  const size_t n = p->n, m = p->m;
  vr_status st = check_point(*p, params, "given", err);
  if (st != VR_OK) return st;
  std::vector<size_t> free;
  for (size_t j = 0; j < n; ++j)
    if (!p->fixed[j]) free.push_back(j);
  const size_t nf = free.size();
  if (m < nf)
    return vr_error_set(err, VR_E_ARG, "%zu residuals cannot determine %zu free parameters",
                        m, nf);
  if (scale && m == nf)
    return vr_error_set(err, VR_E_ARG, "cannot scale by the reduced chi-square: %zu residuals "
                        "and %zu free parameters leave no degree of freedom", m, nf);

  Model model(*p, params);
  std::vector<double> f(m), J(m * n);
  if (!model.residuals(params, f.data()))
    return vr_error_set(err, VR_E_NUMERIC, "the residual callback failed (or gave a non-finite "
                        "residual) at the parameters of the covariance");
  /* Uncertainties always from central differences, whatever the solver used. */
  const bool forward = p->forward;
  p->forward = false;
  const bool jac_ok = model.jacobian(params, f.data(), J.data());
  p->forward = forward;
  if (!jac_ok)
    return vr_error_set(err, VR_E_NUMERIC, "the Jacobian could not be evaluated at the "
                        "parameters of the covariance");

  std::fill(cov, cov + n * n, 0.0);
  if (nf == 0) return VR_OK;

  /* Columns are scaled to unit norm before the SVD, so the rank test sees
   * how well the data separate the parameters, not the ratio of their
   * units (nm against nm^2 would otherwise look singular). */
  Eigen::MatrixXd Js(m, nf);
  Eigen::VectorXd d(nf);
  for (size_t k = 0; k < nf; ++k) {
    for (size_t i = 0; i < m; ++i) Js(i, k) = J[i * n + free[k]];
    d(k) = Js.col(k).norm();
    if (!(d(k) > 0))
      return vr_error_set(err, VR_E_NUMERIC, "parameter %zu is not determined: the residuals "
                          "do not depend on it at these values (zero Jacobian column)", free[k]);
    Js.col(k) /= d(k);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Js, Eigen::ComputeThinV);
  const Eigen::VectorXd &sv = svd.singularValues();
  const Eigen::MatrixXd &V = svd.matrixV();
  const double smax = sv(0);
  const double rcond = smax > 0 ? (sv(nf - 1) / smax) * (sv(nf - 1) / smax) : 0;
  if (!(rcond >= kMinReciprocalCondition)) {
    /* Each right singular vector of a negligible singular value is a
     * direction the data do not see; its large components are the
     * parameters involved. */
    std::string what;
    for (size_t k = 0; k < nf; ++k) {
      const double r = smax > 0 ? (sv(k) / smax) * (sv(k) / smax) : 0;
      if (r >= kMinReciprocalCondition) continue;
      std::vector<size_t> involved;
      for (size_t q = 0; q < nf; ++q)
        if (std::fabs(V(q, k)) >= 0.1) involved.push_back(free[q]);
      if (!what.empty()) what += "; ";
      if (involved.size() == 1)
        what += "parameter " + join_indices(involved) + " is not determined by the data";
      else
        what += "parameters " + join_indices(involved) +
                " are perfectly correlated (only a combination of them is determined)";
    }
    char head[160];
    std::snprintf(head, sizeof head, "the Jacobian is rank deficient (reciprocal condition "
                  "number of J^T J %.3g < %.0e): ", rcond, kMinReciprocalCondition);
    return fail(err, VR_E_NUMERIC, head + what);
  }

  double factor = 1;
  if (scale) {
    double chi2 = 0;
    for (double r : f) chi2 += r * r;
    factor = chi2 / (double)(m - nf);
  }
  /* (J^T J)^-1 = D^-1 V S^-2 V^T D^-1 for J = U S V^T D. */
  Eigen::MatrixXd W = V * sv.cwiseInverse().asDiagonal();
  Eigen::MatrixXd C = W * W.transpose();
  for (size_t a = 0; a < nf; ++a)
    for (size_t b = 0; b < nf; ++b)
      cov[free[a] * n + free[b]] = factor * C(a, b) / (d(a) * d(b));
  return VR_OK;
}

}  // namespace

extern "C" {

vr_lsq_options vr_lsq_default_options(void) {
  vr_lsq_options o;
  o.max_iterations = 200;
  o.function_tolerance = 1e-12;
  o.gradient_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.loss = VR_LOSS_NONE;
  o.loss_scale = 1;
  o.num_threads = 1;
  return o;
}

vr_lsq *vr_lsq_create(size_t nparams, size_t nresiduals, vr_lsq_residual_fn fn, void *user,
                      bool analytic_jacobian, vr_error *err) {
  try {
    if (!fn) {
      vr_error_set(err, VR_E_ARG, "vr_lsq_create: the residual callback is NULL");
      return nullptr;
    }
    if (nparams == 0 || nresiduals == 0) {
      vr_error_set(err, VR_E_ARG, "vr_lsq_create: need at least one parameter and one residual "
                   "(got %zu and %zu)", nparams, nresiduals);
      return nullptr;
    }
    /* Ceres counts in int; the Jacobian also has to fit in memory. */
    const size_t imax = (size_t)std::numeric_limits<int>::max();
    if (nparams > imax || nresiduals > imax || nresiduals > SIZE_MAX / sizeof(double) / nparams) {
      vr_error_set(err, VR_E_ARG, "vr_lsq_create: %zu parameters and %zu residuals is too large",
                   nparams, nresiduals);
      return nullptr;
    }
    auto p = std::make_unique<vr_lsq>();
    p->n = nparams;
    p->m = nresiduals;
    p->fn = fn;
    p->user = user;
    p->analytic = analytic_jacobian;
    p->lower.assign(nparams, -INFINITY);
    p->upper.assign(nparams, INFINITY);
    p->step.assign(nparams, kDefaultStep);
    p->fixed.assign(nparams, 0);
    return p.release();
  } catch (...) {
    fail_exception(err, "vr_lsq_create");
    return nullptr;
  }
}

void vr_lsq_destroy(vr_lsq *p) { delete p; }

vr_status vr_lsq_set_bounds(vr_lsq *p, size_t index, double lower, double upper,
                            vr_error *err) {
  if (!p) return vr_error_set(err, VR_E_ARG, "vr_lsq_set_bounds: problem is NULL");
  if (index >= p->n)
    return vr_error_set(err, VR_E_ARG, "parameter %zu: no such parameter (the problem has %zu)",
                        index, p->n);
  if (std::isnan(lower) || std::isnan(upper) || lower == INFINITY || upper == -INFINITY)
    return vr_error_set(err, VR_E_ARG, "parameter %zu: invalid bounds [%g, %g]", index, lower,
                        upper);
  /* An empty interval would make Ceres' projected steps meaningless; a
   * parameter pinned to one value is what vr_lsq_set_fixed is for. */
  if (!(lower < upper))
    return vr_error_set(err, VR_E_ARG, "parameter %zu: lower bound %g is not below upper bound "
                        "%g (use vr_lsq_set_fixed to hold a parameter)", index, lower, upper);
  p->lower[index] = lower;
  p->upper[index] = upper;
  return VR_OK;
}

vr_status vr_lsq_set_fixed(vr_lsq *p, size_t index, bool fixed, vr_error *err) {
  if (!p) return vr_error_set(err, VR_E_ARG, "vr_lsq_set_fixed: problem is NULL");
  if (index >= p->n)
    return vr_error_set(err, VR_E_ARG, "parameter %zu: no such parameter (the problem has %zu)",
                        index, p->n);
  p->fixed[index] = fixed ? 1 : 0;
  return VR_OK;
}

vr_status vr_lsq_set_forward_differences(vr_lsq *p, bool forward, vr_error *err) {
  if (!p) return vr_error_set(err, VR_E_ARG, "vr_lsq_set_forward_differences: problem is NULL");
  p->forward = forward;
  return VR_OK;
}

vr_status vr_lsq_set_step(vr_lsq *p, size_t index, double relative_step, vr_error *err) {
  if (!p) return vr_error_set(err, VR_E_ARG, "vr_lsq_set_step: problem is NULL");
  if (index >= p->n)
    return vr_error_set(err, VR_E_ARG, "parameter %zu: no such parameter (the problem has %zu)",
                        index, p->n);
  if (!(relative_step > 0 && relative_step < 1))
    return vr_error_set(err, VR_E_ARG, "parameter %zu: relative step %g is not in (0, 1)", index,
                        relative_step);
  p->step[index] = relative_step;
  return VR_OK;
}

vr_status vr_lsq_solve(vr_lsq *p, double *params, const vr_lsq_options *options,
                       vr_lsq_summary *summary, vr_error *err) {
  try {
    return solve(p, params, options, summary, err);
  } catch (...) {
    if (summary) {
      summary->termination = VR_LSQ_FAILURE;
      summary_message(summary, "internal error");
    }
    return fail_exception(err, "vr_lsq_solve");
  }
}

vr_status vr_lsq_covariance(vr_lsq *p, const double *params, bool scale_by_reduced_chi2,
                            double *covariance_out, vr_error *err) {
  try {
    return covariance(p, params, scale_by_reduced_chi2, covariance_out, err);
  } catch (...) {
    return fail_exception(err, "vr_lsq_covariance");
  }
}

}  // extern "C"
