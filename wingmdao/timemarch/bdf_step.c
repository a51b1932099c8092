/* Newton iterations of one BDF step in compiled code (wingmdao.timemarch.fast_step).
 *
 * The same iteration as wingmdao.timemarch.bdf._StepSolver.solve (docs/time-marching.md,
 * Sec. 2): residual R(x, alpha x + hist, p, q) and Newton matrix dR/dx + alpha dR/dxdot from the
 * CasADi-generated C functions (called through their pointers), the matrix factored by a sparse
 * left-looking LU with partial pivoting (Gilbert & Peierls, SIAM J. Sci. Stat. Comput. 9, 1988;
 * the formulation of T. A. Davis, Direct Methods for Sparse Linear Systems, SIAM 2006, Ch. 6:
 * depth-first reach, sparse triangular solve, pivot search per column), in the system's column
 * order Q (P A Q = L U; natural when qcol is NULL): the fill-reducing node-local order of
 * wingmdao.timemarch.lu_orders, which also shortens every back-substitution of the march.
 * Exact zeros of the Newton matrix (CasADi patterns are structural) are skipped.
 *
 * Compile: gcc -shared -fPIC -O2 -ffp-contract=off (no fused multiply-adds: the arithmetic of
 * the convergence tests is the same as numpy's).
 */
#include <math.h>
#include <string.h>

typedef long long int casadi_int;
typedef int (*casadi_fun)(const double **arg, double **res, casadi_int *iw, double *w, int mem);

typedef struct {
    int n;                        /* states */
    /* residual function R(x, xdot, p, q) */
    casadi_fun res_f;
    const double **res_arg; double **res_res; casadi_int *res_iw; double *res_w;
    /* Newton function (R, nz of dR/dx + alpha dR/dxdot)(x, xdot, p, q, alpha) */
    casadi_fun jac_f;
    const double **jac_arg; double **jac_res; casadi_int *jac_iw; double *jac_w;
    const int *Ap, *Ai;           /* CSC pattern of the Newton matrix (n + 1, nnz) */
    double *Ax;                   /* its values (Newton function output) */
    const double *p, *q;          /* parameters, forcing of the step */
    double *xdot, *r, *dx;        /* n each: rate, residual, Newton step */
    double alpha_buf;             /* alpha (Newton function input) */
    /* LU factors P A = L U (L unit lower, diagonal first; U diagonal last) */
    int *Lp, *Li, *Up, *Ui, *pinv;
    double *Lx, *Ux;
    int cap_L, cap_U;             /* capacities of Li/Lx and Ui/Ux */
    double *work;                 /* n */
    int *xi, *mark;               /* 2 n, n */
    int stamp;
    /* Newton options */
    double atol, xtol, contraction;
    int max_iter, modified;
    /* state kept across steps */
    int lu_valid;
    double lu_alpha;
    int factorizations;
    /* outputs of the last call */
    int iterations, fail_iteration;
    double *hist;                 /* n: BDF history term of wm_march */
    const int *qcol;              /* n: column order Q (column k of A Q is A(:, qcol[k])), or NULL */
} wm_step;

enum { WM_OK = 0, WM_RES_NONFINITE = 1, WM_STEP_NONFINITE = 2, WM_SINGULAR = 3,
       WM_NO_CONVERGENCE = 4, WM_CAPACITY = 5, WM_FUNCTION = 6 };

/* depth-first search from row j through the columns of L found so far (Davis 2006, cs_dfs) */
static int reach_dfs(wm_step *s, int j, int top, int *stack, int *pstack) {
    int head = 0;
    const int *Lp = s->Lp, *Li = s->Li, *pinv = s->pinv;
    int *mark = s->mark, stamp = s->stamp;
    stack[0] = j;
    while (head >= 0) {
        j = stack[head];
        int jnew = pinv[j];
        if (mark[j] != stamp) {
            mark[j] = stamp;
            pstack[head] = (jnew < 0) ? 0 : Lp[jnew];
        }
        int done = 1, p2 = (jnew < 0) ? 0 : Lp[jnew + 1];
        for (int p = pstack[head]; p < p2; p++) {
            int i = Li[p];
            if (mark[i] == stamp) continue;
            pstack[head] = p + 1;
            stack[++head] = i;
            done = 0;
            break;
        }
        if (done) {
            head--;
            stack[--top] = j;
        }
    }
    return top;
}

/* LU of the Newton matrix in s->Ax; returns WM_OK, WM_SINGULAR or WM_CAPACITY */
static int factor(wm_step *s) {
    int n = s->n, lnz = 0, unz = 0;
    const int *Ap = s->Ap, *Ai = s->Ai;
    const double *Ax = s->Ax;
    int *Lp = s->Lp, *Li = s->Li, *Up = s->Up, *Ui = s->Ui, *pinv = s->pinv, *xi = s->xi;
    double *Lx = s->Lx, *Ux = s->Ux, *x = s->work;
    for (int i = 0; i < n; i++) { pinv[i] = -1; x[i] = 0.0; }
    for (int k = 0; k < n; k++) {
        if (lnz + n > s->cap_L || unz + n > s->cap_U) return WM_CAPACITY;
        Lp[k] = lnz;
        Up[k] = unz;
        /* pattern of L \ A(:, k): reach of its nonzero rows */
        if (++s->stamp == 0x7fffffff) { memset(s->mark, 0, (size_t)n * sizeof(int)); s->stamp = 1; }
        int top = n, c = s->qcol ? s->qcol[k] : k;      /* column k of A Q */
        for (int p = Ap[c]; p < Ap[c + 1]; p++) {
            if (Ax[p] == 0.0) continue;
            if (s->mark[Ai[p]] != s->stamp) top = reach_dfs(s, Ai[p], top, xi, xi + n);
        }
        for (int p = Ap[c]; p < Ap[c + 1]; p++) x[Ai[p]] = Ax[p];
        /* sparse triangular solve with the unit lower L (rows in original order) */
        for (int px = top; px < n; px++) {
            int j = xi[px], J = pinv[j];
            if (J < 0) continue;
            double xj = x[j];
            for (int p = Lp[J] + 1; p < Lp[J + 1]; p++) x[Li[p]] -= Lx[p] * xj;
        }
        /* partial pivoting: largest magnitude among the rows not yet pivotal */
        int ipiv = -1;
        double a = -1.0;
        for (int px = top; px < n; px++) {
            int i = xi[px];
            if (pinv[i] < 0) {
                double t = fabs(x[i]);
                if (t > a) { a = t; ipiv = i; }
            } else {
                Ui[unz] = pinv[i];
                Ux[unz++] = x[i];
            }
        }
        if (ipiv == -1 || !(a > 0.0) || !isfinite(a)) {
            for (int px = top; px < n; px++) x[xi[px]] = 0.0;
            return WM_SINGULAR;
        }
        if (pinv[c] < 0 && fabs(x[c]) >= a) ipiv = c;   /* the diagonal A(c, c) on ties */
        double pivot = x[ipiv];
        Ui[unz] = k;
        Ux[unz++] = pivot;
        pinv[ipiv] = k;
        Li[lnz] = ipiv;
        Lx[lnz++] = 1.0;
        for (int px = top; px < n; px++) {
            int i = xi[px];
            if (pinv[i] < 0) {
                Li[lnz] = i;
                Lx[lnz++] = x[i] / pivot;
            }
            x[i] = 0.0;
        }
    }
    Lp[n] = lnz;
    Up[n] = unz;
    for (int p = 0; p < lnz; p++) Li[p] = pinv[Li[p]];
    return WM_OK;
}

/* dx = A^-1 b with the factors of P A Q (b and dx may not alias): L U y = P b, dx = Q y */
static void lu_solve(const wm_step *s, const double *b, double *out) {
    int n = s->n;
    double *y = s->work;
    const int *Lp = s->Lp, *Li = s->Li, *Up = s->Up, *Ui = s->Ui, *pinv = s->pinv;
    const double *Lx = s->Lx, *Ux = s->Ux;
    for (int i = 0; i < n; i++) y[pinv[i]] = b[i];
    for (int j = 0; j < n; j++) {            /* L y = P b */
        double yj = y[j];
        if (yj == 0.0) continue;
        for (int p = Lp[j] + 1; p < Lp[j + 1]; p++) y[Li[p]] -= Lx[p] * yj;
    }
    for (int j = n - 1; j >= 0; j--) {       /* U x = y */
        double xj = y[j] / Ux[Up[j + 1] - 1];
        y[j] = xj;
        if (xj == 0.0) continue;
        for (int p = Up[j]; p < Up[j + 1] - 1; p++) y[Ui[p]] -= Ux[p] * xj;
    }
    if (s->qcol) {
        for (int j = 0; j < n; j++) out[s->qcol[j]] = y[j];
    } else {
        memcpy(out, y, (size_t)n * sizeof(double));
    }
}

/* max |v|; returns NaN when an entry is NaN (like numpy's max) */
static double max_abs(const double *v, int n) {
    double m = 0.0;
    for (int i = 0; i < n; i++) {
        double t = fabs(v[i]);
        if (t != t) return t;
        if (t > m) m = t;
    }
    return m;
}

static int eval_residual(wm_step *s, const double *x, const double *hist, double alpha) {
    int n = s->n;
    for (int i = 0; i < n; i++) {
        double t = x[i] * alpha;
        s->xdot[i] = t + hist[i];
    }
    s->res_arg[0] = x; s->res_arg[1] = s->xdot; s->res_arg[2] = s->p; s->res_arg[3] = s->q;
    s->res_res[0] = s->r;
    return s->res_f(s->res_arg, s->res_res, s->res_iw, s->res_w, 0);
}

static int eval_newton(wm_step *s, const double *x, const double *hist, double alpha) {
    int n = s->n;
    for (int i = 0; i < n; i++) {
        double t = x[i] * alpha;
        s->xdot[i] = t + hist[i];
    }
    s->alpha_buf = alpha;
    s->jac_arg[0] = x; s->jac_arg[1] = s->xdot; s->jac_arg[2] = s->p; s->jac_arg[3] = s->q;
    s->jac_arg[4] = &s->alpha_buf;
    s->jac_res[0] = s->r; s->jac_res[1] = s->Ax;
    return s->jac_f(s->jac_arg, s->jac_res, s->jac_iw, s->jac_w, 0);
}

/* Solve R(x, alpha x + hist, p, q) = 0 from x (updated in place). Returns a WM_ code; on
 * success s->iterations is the number of Newton steps taken. On failure s->r holds the residual
 * of the error message and s->fail_iteration the iteration. */
int wm_bdf_step(wm_step *s, double *x, const double *hist, double alpha) {
    int n = s->n;
    s->iterations = 0;
    s->fail_iteration = 0;
    if (n == 0) return WM_OK;
    int reuse = s->modified && s->lu_valid && s->lu_alpha == alpha;
    int have_prev = 0;
    double prev_step = 0.0, prev_norm = INFINITY, x_max = 0.0, first_norm = 0.0;
    for (int it = 1; it <= s->max_iter; it++) {
        if (eval_residual(s, x, hist, alpha)) { s->fail_iteration = it; return WM_FUNCTION; }
        double norm = max_abs(s->r, n);
        if (!isfinite(norm)) { s->fail_iteration = it; return WM_RES_NONFINITE; }
        if (norm <= s->atol) { s->iterations = it - 1; return WM_OK; }
        if (it == 1) first_norm = norm;
        /* round-off floor (bdf.FLOOR_RATIO = 1e-10) */
        if (have_prev && norm >= 0.5 * prev_norm
                && (prev_step <= 1e3 * s->xtol * (1.0 + x_max) || norm <= 1e-10 * first_norm)) {
            s->iterations = it - 1;
            return WM_OK;
        }
        prev_norm = norm;
        if (!reuse) {
            s->lu_valid = 0;
            if (eval_newton(s, x, hist, alpha)) { s->fail_iteration = it; return WM_FUNCTION; }
            int st = factor(s);
            if (st != WM_OK) { s->fail_iteration = it; return st; }
            s->lu_valid = 1;
            s->lu_alpha = alpha;
            s->factorizations++;
        }
        lu_solve(s, s->r, s->dx);
        double step = max_abs(s->dx, n);
        if (!isfinite(step)) { s->fail_iteration = it; return WM_STEP_NONFINITE; }
        for (int i = 0; i < n; i++) x[i] -= s->dx[i];
        x_max = max_abs(x, n);
        double tol = s->xtol * (1.0 + x_max);
        if (step <= tol) { s->iterations = it; return WM_OK; }
        if (have_prev && step < prev_step) {
            double theta = step / prev_step;
            if (theta / (1.0 - theta) * step <= tol) { s->iterations = it; return WM_OK; }
        }
        if (s->modified) reuse = !have_prev || step <= s->contraction * prev_step;
        prev_step = step;
        have_prev = 1;
    }
    s->fail_iteration = s->max_iter;
    if (eval_residual(s, x, hist, alpha)) return WM_FUNCTION;
    return WM_NO_CONVERGENCE;
}

/* Steps first..end-1 of a march (bdf.march: BDF1 at step 1, BDF2 after; predictor x_0, then
 * linear, then quadratic extrapolation), the same floating-point operations as the Python loop.
 * X: (n_time, n) states, rows < first known; Q: (n_time, nq) forcing; iters: (n_time,) ints.
 * Returns WM_OK or the status of the failed step, whose index is stored in *failed. */
int wm_march(wm_step *s, double *X, double *Q, int nq, double dt, int first, int end,
             long long *iters, int *failed) {
    int n = s->n;
    for (int k = first; k < end; k++) {
        double *x = X + (size_t)k * n, *x1 = x - n;
        double *x2 = (k >= 2) ? x1 - n : x1, *x3 = (k >= 3) ? x2 - n : x2;   /* used from steps 2, 3 */
        double a0 = (k == 1) ? 1.0 : 1.5, a1 = (k == 1) ? -1.0 : -2.0, a2 = 0.5;
        double *h = s->hist;
        if (k == 1) {
            for (int i = 0; i < n; i++) { double t = a1 * x1[i]; h[i] = (t + 0.0) / dt; x[i] = x1[i]; }
        } else {
            for (int i = 0; i < n; i++) { double t = a1 * x1[i], u = a2 * x2[i]; h[i] = (t + u) / dt; }
            if (k == 2) {
                for (int i = 0; i < n; i++) { double t = 2.0 * x1[i]; x[i] = t - x2[i]; }
            } else {
                for (int i = 0; i < n; i++) {
                    double t = 3.0 * x1[i], u = 3.0 * x2[i], v = t - u;
                    x[i] = v + x3[i];
                }
            }
        }
        s->q = Q + (size_t)k * nq;
        int st = wm_bdf_step(s, x, h, a0 / dt);
        if (st != WM_OK) { *failed = k; return st; }
        iters[k] = s->iterations;
    }
    return WM_OK;
}

/* the LU alone, for tests: factor the values Ax of the pattern, solve for b */
int wm_lu_test(wm_step *s, double *b, double *out) {
    int st = factor(s);
    if (st != WM_OK) return st;
    lu_solve(s, b, out);
    return WM_OK;
}
