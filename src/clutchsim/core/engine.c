/* The integration loop of clutchsim in C (clutchsim/core/engine.c): the engine of every
   run of a compiled method, called through ctypes by clutchsim/core/cengine.py (and from
   numba by a sweep's batch, cl_integrate_nb).

   It began as a line-by-line port of the numba loop that clutchsim had before (deleted in
   issue 41): the same arithmetic in the same order, the same bits on every example
   (tests/core/test_cengine.py compares the engine's runs with that loop's, recorded).

   The plant's functions arrive as C function pointers (the `cs_` entries of a printed
   plant).  Output rows and the event log are written into the caller's arrays; when those
   are full the engine continues in memory of its own (malloc, doubled as needed), which
   the caller takes over and releases with cl_free.  The sizes of the plant are bounded by
   the constants below (a larger plant returns UNSUPPORTED: cengine.py runs it on scipy's
   reference backend). */

#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L   /* clock_gettime under -std=c99 */
#endif
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void (*kern_t)(double, double *, double *, double *, double *);
typedef int (*reset_t)(double, double *, double *, double *, int);
typedef void (*jac_t)(double, double *, double *, double *, double *, int);
typedef int (*fac_t)(double, double *, int, double *);
typedef void (*sol_t)(double *, double *, double *, int, int);

/* clutchsim.core.status: Code, Action */
enum { DONE = 0, EVENT_STOP = 1, EVENT_FAIL = 2, MAX_STEPS = 3, WALL_TIME = 4,
       STEP_COLLAPSE = 5, CHATTER = 6, NON_FINITE = 7, JAC_NON_FINITE = 8 };
enum { UNSUPPORTED = -1, NO_MEMORY = -2 };
enum { A_CONTINUE = 0, A_STATE_CHANGED = 1, A_STOP = 2, A_FAIL = 3, A_PASS = 4 };
/* slots of the statistics and of the option vectors (cengine.py's S_*, O_*, I_*, M_*) */
enum { S_STEPS, S_REJECTED, S_RHS, S_JAC, S_LU, S_EVENTS, S_OUTPUT, S_EV_CALLS, N_STATS };
enum { O_RTOL, O_ATOL, O_H0, O_HMAX, O_HMIN, O_WALL, O_CHATTER_WINDOW, O_DT_OUT,
       O_EVENT_TOL, O_LU_REUSE };
enum { I_MAX_STEPS, I_CHATTER_N, I_MAX_OUTPUT, I_QUADRATURES, I_EXACT_JAC, I_JAC_MAX_AGE,
       I_FACTOR_SIZE, I_STOP };
enum { M_FAMILY, M_GAMMA, M_Q, M_DENSE, M_W, M_FSAL };
enum { C_KIND, C_SAFETY, C_MIN, C_MAX, C_B1, C_B2, C_B3 };
enum { DENSE_HERMITE = 0, DENSE_STAGES = 1, DENSE_POLY = 2 };
#define N_SAMPLES 4
#define PROBE 0.1
#define MAX_PROBES 4
#define VALLEY_PROBES 40
#define VALLEY_DEPTH 1e-12
#define NEAR_ZERO 2.0
#define TERM_W 10
#define SMALL_TABLE 16
#define SQRT_EPS 1.4901161193847656e-08
#define EPS 2.220446049250313e-16
#define MAXN 64
#define MAXS 16
#define MAXEV 128
#define MAXOUT 512
#define MAXF 8192
#define MAXRING 4096

/* Python's max(a, b) and min(a, b) for floats (the first unless the second is larger or
   smaller; not fmax/fmin, which differ on NaN and signed zeros) */
static inline double pmax(double a, double b) { return b > a ? b : a; }
static inline double pmin(double a, double b) { return b < a ? b : a; }

/* ---- inputs (the signal bank of signals.py) ---- */
static inline int interval(const double *a, int o, int n, double x) {
    int lo, hi, i;
    if (n <= SMALL_TABLE) {
        lo = 0;
        for (i = 1; i < n - 1; i++) lo += a[o + i] <= x ? 1 : 0;
        return lo;
    }
    lo = 0;
    hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (a[o + mid] <= x) lo = mid;
        else hi = mid;
    }
    return lo;
}

static double table_value(const double *d, int o, int n, int hit_knots, double t, double t_ref) {
    double key = hit_knots ? t_ref : t, dt;
    int v = o + n, lo, hi;
    if (key < d[o] || n == 1) return d[v];
    if (key >= d[o + n - 1]) return d[v + n - 1];
    lo = interval(d, o, n, key);
    hi = lo + 1;
    dt = d[o + hi] - d[o + lo];
    if (dt <= 0.0) return d[v + hi];
    return d[v + lo] + (d[v + hi] - d[v + lo]) * (t - d[o + lo]) / dt;
}

static void eval_inputs(const double *d, double t, double t_ref, double *u) {
    int ch_last = -1, i;
    for (i = 0; i < (int)d[0]; i++) {
        int b = 1 + i * TERM_W, k = (int)d[b + 1], q = b + 4, ch;
        double val;
        if (k == 0) val = d[q];
        else if (k == 1) val = d[q + 2] + (t_ref >= d[q] ? d[q + 1] : 0.0);
        else if (k == 2) {
            if (t_ref < d[q]) val = d[q + 3];
            else if (t_ref >= d[q] + d[q + 1]) val = d[q + 3] + d[q + 2];
            else val = d[q + 3] + d[q + 2] * (t - d[q]) / d[q + 1];
        } else if (k == 3) {
            if (t_ref < d[q + 4]) val = d[q + 3];
            else val = d[q + 3] + d[q] * sin(2.0 * 3.141592653589793 * d[q + 1] * (t - d[q + 4])
                                             + d[q + 2]);
        } else if (k == 4) {
            if (t_ref < d[q + 4]) val = d[q + 3];
            else {
                double phase = (t_ref - d[q + 4]) / d[q + 2], frac = phase - floor(phase);
                val = d[q + 3] + (frac < d[q + 1] ? d[q] : 0.0);
            }
        } else val = table_value(d, (int)d[b + 2], (int)d[b + 3], d[q] != 0.0, t, t_ref);
        ch = (int)d[b];
        if (ch != ch_last) { u[ch] = val; ch_last = ch; }
        else u[ch] += val;
    }
}

/* ---- the run's context ---- */
typedef struct {
    kern_t rhs, events, outputs;
    reset_t reset;
    jac_t jac;
    fac_t factor;
    sol_t solve;
    const double *bank;
    double *p, *u, *uc;
    int64_t *stats;
    int n, nd, n_ev, dkind;
    double dense[5 * MAXN];
} Ctx;

static inline void inputs_at(Ctx *x, double t, double t_ref) {
    if (t != x->uc[0] || t_ref != x->uc[1]) {
        eval_inputs(x->bank, t, t_ref, x->u);
        x->uc[0] = t;
        x->uc[1] = t_ref;
    }
}

static int first_nonfinite(const double *v, int n) {
    int i;
    for (i = 0; i < n; i++) if (!isfinite(v[i])) return i;
    return -1;
}

static inline int all_finite(const double *v, int n) {
    double acc = 0.0;
    int i;
    for (i = 0; i < n; i++) acc += v[i] * 0.0;
    return acc == 0.0;
}

static double norm(const double *err, const double *y, const double *y_new, int n,
                   double rtol, double atol) {
    double s = 0.0;
    int i;
    for (i = 0; i < n; i++) {
        double sc = atol + rtol * pmax(fabs(y[i]), fabs(y_new[i])), e = err[i] / sc;
        s += e * e;
    }
    return sqrt(s / (n > 1 ? n : 1));
}

static inline int crossed(double g_old, double g_new, int64_t direction) {
    return (direction >= 0 && g_old < 0.0 && g_new >= 0.0)
        || (direction <= 0 && g_old > 0.0 && g_new <= 0.0);
}

static inline int may_hide_crossing(double g_prev, double g0, double g1) {
    double change = fabs(g1 - g0) + fabs(g0 - g_prev);
    return pmin(fabs(g0), fabs(g1)) <= NEAR_ZERO * change;
}

static inline double round_off(const double *y, int n) {
    double scale = 1.0;
    int i;
    for (i = 0; i < n; i++) scale = pmax(scale, fabs(y[i]));
    return 64.0 * EPS * scale;
}

static void place(const double *g_pre, double *g_post, const double *y, int n, int n_ev,
                  double *placed) {
    double tiny = round_off(y, n);
    int k;
    for (k = 0; k < n_ev; k++) {
        if (g_post[k] != g_pre[k] && g_post[k] != 0.0 && fabs(g_post[k]) <= tiny) g_post[k] = 0.0;
        placed[k] = (g_post[k] == 0.0 && g_pre[k] != 0.0) ? 1.0 : 0.0;
    }
}

static double controller_factor(const double *ctrl, double q, double e, double e_old,
                                double e_older, double h, double h_old, int first) {
    double kind = ctrl[C_KIND], safety = ctrl[C_SAFETY], fmn = ctrl[C_MIN], fmx = ctrl[C_MAX];
    double ee = pmax(e, 1e-10), fac = safety * pow(ee, -1.0 / q);
    if (kind == 1.0 && !first) {
        double pred = safety * (h / h_old) * pow(e_old / (ee * ee), 1.0 / q);
        fac = pmin(fac, pred);
    } else if (kind == 2.0) {
        fac = safety * pow(ee, -ctrl[C_B1] / q);
        if (!first)
            fac *= pow(pmax(e_old, 1e-10), -ctrl[C_B2] / q) * pow(pmax(e_older, 1e-10), -ctrl[C_B3] / q);
    }
    if (e == 0.0) fac = fmx;
    return pmin(fmx, pmax(fmn, fac));
}

static double starting_step(Ctx *x, double t, const double *y, const double *f0, double *ytmp,
                            double *ftmp, double atol, double rtol, double q, double h_max) {
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, h, h1;
    int i, n = x->n;
    for (i = 0; i < n; i++) {
        double sc = atol + rtol * fabs(y[i]), a = y[i] / sc, b = f0[i] / sc;
        d0 += a * a;
        d1 += b * b;
    }
    d0 = sqrt(d0 / n);
    d1 = sqrt(d1 / n);
    h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h = pmin(h, h_max);
    for (i = 0; i < n; i++) ytmp[i] = y[i] + h * f0[i];
    x->rhs(t + h, ytmp, x->u, x->p, ftmp);
    x->stats[S_RHS] += 1;
    for (i = 0; i < n; i++) {
        double sc = atol + rtol * fabs(y[i]), v = (ftmp[i] - f0[i]) / sc;
        d2 += v * v;
    }
    d2 = sqrt(d2 / n) / h;
    if (pmax(d1, d2) <= 1e-15) h1 = pmax(1e-6, h * 1e-3);
    else h1 = pow(0.01 / pmax(d1, d2), 1.0 / (q + 1.0));
    return pmin(pmin(100 * h, h1), h_max);
}

/* ---- linear algebra ---- */
static int invert(const double *J, double c, double *M, int64_t *piv, int n, int nd) {
    int i, j, k;
    for (i = 0; i < n; i++) {
        for (j = 0; j < nd; j++) M[i * n + j] = -J[i * n + j];
        M[i * n + i] = c - J[i * n + i];
    }
    for (i = nd; i < n; i++) M[i * n + i] = 1.0 / c;
    for (k = 0; k < nd; k++) {
        int m = k;
        double big = fabs(M[k * n + k]), inv;
        for (i = k + 1; i < nd; i++)
            if (fabs(M[i * n + k]) > big) { big = fabs(M[i * n + k]); m = i; }
        piv[k] = m;
        if (big == 0.0 || isnan(big)) return 0;
        if (m != k)
            for (j = 0; j < nd; j++) { double tmp = M[k * n + j]; M[k * n + j] = M[m * n + j]; M[m * n + j] = tmp; }
        inv = 1.0 / M[k * n + k];
        M[k * n + k] = 1.0;
        for (j = 0; j < nd; j++) M[k * n + j] *= inv;
        for (i = 0; i < nd; i++) {
            double f = M[i * n + k];
            if (i != k && f != 0.0) {
                M[i * n + k] = 0.0;
                for (j = 0; j < nd; j++) M[i * n + j] -= f * M[k * n + j];
            }
        }
    }
    for (k = nd - 1; k >= 0; k--) {
        int m = (int)piv[k];
        if (m != k)
            for (i = 0; i < nd; i++) { double tmp = M[i * n + k]; M[i * n + k] = M[i * n + m]; M[i * n + m] = tmp; }
    }
    return 1;
}

static void solve_into_row(const double *M, const double *b, double *X, int r, int n, int nd) {
    int i, j;
    for (i = 0; i < nd; i++) {
        double s = 0.0;
        for (j = 0; j < nd; j++) s += M[i * n + j] * b[j];
        X[r * n + i] = s;
    }
    for (i = nd; i < n; i++) {
        double s = b[i];
        for (j = 0; j < nd; j++) s -= M[i * n + j] * X[r * n + j];
        X[r * n + i] = M[i * n + i] * s;
    }
}

/* ---- steps ---- */
static int jacobian(Ctx *x, double t, const double *y, double t_ref, const double *f0,
                    double atol_over_rtol, double *ytmp, double *ftmp, double *J, double *dfdt,
                    int exact) {
    int n = x->n, i, j, calls = 0;
    double dt;
    inputs_at(x, t, t_ref);
    if (exact) x->jac(t, (double *)y, x->u, x->p, J, n);
    else {
        for (i = 0; i < n; i++) ytmp[i] = y[i];
        for (j = 0; j < x->nd; j++) {
            double delta = SQRT_EPS * pmax(pmax(fabs(y[j]), atol_over_rtol), 1e-10);
            ytmp[j] = y[j] + delta;
            delta = ytmp[j] - y[j];
            x->rhs(t, ytmp, x->u, x->p, ftmp);
            for (i = 0; i < n; i++) J[i * n + j] = (ftmp[i] - f0[i]) / delta;
            ytmp[j] = y[j];
        }
        calls = x->nd;
    }
    dt = SQRT_EPS * pmax(fabs(t), 1e-3);
    inputs_at(x, t + dt, t_ref);
    x->rhs(t + dt, (double *)y, x->u, x->p, ftmp);
    for (i = 0; i < n; i++) dfdt[i] = (ftmp[i] - f0[i]) / dt;
    return calls + 1;
}

static inline void stage_argument(double *ytmp, const double *y, const double *A, int s, int st,
                                  const double *K, double scale, int n) {
    int i, j;
    for (i = 0; i < n; i++) ytmp[i] = y[i];
    for (j = 0; j < st; j++) {
        double w = scale * A[st * s + j];
        if (w != 0.0)
            for (i = 0; i < n; i++) ytmp[i] += w * K[j * n + i];
    }
}

typedef struct { const double *a, *C, *c, *d, *m, *e, *H; int s, nh; } Tab;

static int ros_step(Ctx *x, double t, const double *y, double h, double t_ref,
                    const double *f0, const double *dfdt, const double *M, double *F,
                    int structured, double *K, double *ytmp, double *ftmp, double *y_new,
                    double *err, const Tab *tb, const int *ext) {
    int s = tb->s, n = x->n, st, i, j;
    double inv_h = 1.0 / h;
    for (st = 0; st < s; st++) {
        double hd;
        if (st == 0) {
            for (i = 0; i < n; i++) ftmp[i] = f0[i];
        } else {
            double ts;
            if (ext[st] != 0)
                for (i = 0; i < n; i++) ytmp[i] += K[(st - 1) * n + i];
            else stage_argument(ytmp, y, tb->a, s, st, K, 1.0, n);
            ts = t + tb->c[st] * h;
            inputs_at(x, ts, t_ref);
            x->rhs(ts, ytmp, x->u, x->p, ftmp);
        }
        hd = h * tb->d[st];
        if (hd != 0.0)
            for (i = 0; i < n; i++) ftmp[i] += hd * dfdt[i];
        for (j = 0; j < st; j++) {
            double cij = tb->C[st * s + j] * inv_h;
            if (cij != 0.0)
                for (i = 0; i < n; i++) ftmp[i] += cij * K[j * n + i];
        }
        if (structured) x->solve(F, ftmp, K, n, st);
        else solve_into_row(M, ftmp, K, st, n, x->nd);
    }
    if (ext[s] != 0) {
        for (i = 0; i < n; i++) y_new[i] = ytmp[i] + K[(s - 1) * n + i];
    } else {
        for (i = 0; i < n; i++) y_new[i] = y[i];
        for (j = 0; j < s; j++) {
            double mj = tb->m[j];
            if (mj != 0.0)
                for (i = 0; i < n; i++) y_new[i] += mj * K[j * n + i];
        }
    }
    for (i = 0; i < n; i++) err[i] = 0.0;
    for (j = 0; j < s; j++) {
        double ej = tb->e[j];
        if (ej != 0.0)
            for (i = 0; i < n; i++) err[i] += ej * K[j * n + i];
    }
    return s - 1;
}

static int erk_step(Ctx *x, double t, const double *y, double h, double t_ref, double *K,
                    double *ytmp, double *y_new, double *err, const Tab *tb) {
    int s = tb->s, n = x->n, st, i, j;
    for (st = 1; st < s; st++) {
        double ts;
        stage_argument(ytmp, y, tb->a, s, st, K, h, n);
        ts = t + tb->c[st] * h;
        inputs_at(x, ts, t_ref);
        x->rhs(ts, ytmp, x->u, x->p, K + st * n);
    }
    for (i = 0; i < n; i++) { y_new[i] = y[i]; err[i] = 0.0; }
    for (j = 0; j < s; j++) {
        double bj = h * tb->m[j], ej = h * tb->e[j];
        for (i = 0; i < n; i++) {
            y_new[i] += bj * K[j * n + i];
            err[i] += ej * K[j * n + i];
        }
    }
    return s - 1;
}

static void dense_coefficients(Ctx *x, const Tab *tb, const double *K, int nk, const double *y,
                               const double *y_new, const double *f0, const double *f1, double h) {
    int n = x->n, i, j, r;
    double *dense = x->dense;
    int s = x->dkind == DENSE_POLY ? nk : tb->s;
    for (i = 0; i < n; i++) {
        dense[i] = y[i];
        dense[n + i] = y_new[i];
        dense[2 * n + i] = 0.0;
        dense[3 * n + i] = 0.0;
        dense[4 * n + i] = 0.0;
    }
    if (x->dkind == DENSE_HERMITE) {
        for (i = 0; i < n; i++) {
            double delta = y_new[i] - y[i];
            dense[2 * n + i] = h * f0[i] - delta;
            dense[3 * n + i] = 2.0 * delta - h * f0[i] - h * f1[i];
        }
    } else if (x->dkind == DENSE_POLY) {
        for (i = 0; i < n; i++) dense[n + i] = 0.0;
        for (r = 0; r < 4; r++)
            for (j = 0; j < s; j++) {
                double w = h * tb->H[r * s + j];
                if (w != 0.0)
                    for (i = 0; i < n; i++) dense[(r + 1) * n + i] += w * K[j * n + i];
            }
    } else {
        for (r = 0; r < 3; r++)
            for (j = 0; j < s; j++) {
                double w = tb->H[r * s + j];
                if (w != 0.0)
                    for (i = 0; i < n; i++) dense[(r + 2) * n + i] += w * K[j * n + i];
            }
    }
}

static void dense_eval(const Ctx *x, double s, double *out) {
    int n = x->n, i;
    const double *d = x->dense;
    if (x->dkind == DENSE_POLY) {
        for (i = 0; i < n; i++)
            out[i] = d[i] + s * (d[n + i] + s * (d[2 * n + i] + s * (d[3 * n + i] + s * d[4 * n + i])));
    } else {
        double s1 = 1.0 - s;
        for (i = 0; i < n; i++)
            out[i] = d[i] * s1 + s * (d[n + i] + s1 * (d[2 * n + i] + s * (d[3 * n + i] + s * d[4 * n + i])));
    }
}

/* ---- events ---- */
/* A buffer the engine writes and grows: the caller's arrays (owned 0) until they are full,
   then memory of the engine's own, doubled when full (owned 1) */
typedef struct {
    double *t, *y, *u, *o;      /* rows: time, state (n), inputs (n_in), outputs (n_out) */
    int64_t cap;
    int owned;
} Rows;

static void *grown(void *old, int owned, size_t used, size_t size) {
    void *b = owned ? realloc(old, size) : malloc(size);
    if (b && !owned && used) memcpy(b, old, used);
    return b;
}

/* room for one more row (after n_used of them); 0 when memory ran out */
static int rows_room(Rows *r, int64_t n_used, int n, int n_in, int n_out) {
    int64_t cap;
    double *t, *y, *u, *o;
    if (n_used < r->cap) return 1;
    cap = 2 * r->cap + 16;
    t = grown(r->t, r->owned, n_used * sizeof(double), cap * sizeof(double));
    if (t) r->t = t;
    y = grown(r->y, r->owned, n_used * n * sizeof(double), cap * (n > 0 ? n : 1) * sizeof(double));
    if (y) r->y = y;
    u = grown(r->u, r->owned, n_used * n_in * sizeof(double), cap * (n_in > 0 ? n_in : 1) * sizeof(double));
    if (u) r->u = u;
    o = grown(r->o, r->owned, n_used * n_out * sizeof(double), cap * (n_out > 0 ? n_out : 1) * sizeof(double));
    if (o) r->o = o;
    if (!(t && y && u && o)) {        /* what was moved is the engine's: the caller frees it */
        r->owned = r->owned || t || y || u || o;
        return 0;
    }
    r->owned = 1;
    r->cap = cap;
    return 1;
}

typedef struct {
    double *ev_t;
    int64_t *ev_k, *ev_a;
    int64_t cap;
    int owned;
    double ring[MAXRING];
    int64_t ch_n;
    double ch_window;
} Log;

static int log_room(Log *lg, int64_t n_used) {
    int64_t cap;
    double *t;
    int64_t *k, *a;
    if (n_used < lg->cap) return 1;
    cap = 2 * lg->cap + 16;
    t = grown(lg->ev_t, lg->owned, n_used * sizeof(double), cap * sizeof(double));
    if (t) lg->ev_t = t;
    k = grown(lg->ev_k, lg->owned, n_used * sizeof(int64_t), cap * sizeof(int64_t));
    if (k) lg->ev_k = k;
    a = grown(lg->ev_a, lg->owned, n_used * sizeof(int64_t), cap * sizeof(int64_t));
    if (a) lg->ev_a = a;
    if (!(t && k && a)) {
        lg->owned = lg->owned || t || k || a;
        return 0;
    }
    lg->owned = 1;
    lg->cap = cap;
    return 1;
}

/* the reset of event k, logged; the status (DONE, CHATTER, EVENT_STOP, EVENT_FAIL, NO_MEMORY) */
static int apply_event(Ctx *x, Log *lg, double t, double *y, int k, int *action) {
    int64_t ne = x->stats[S_EVENTS];
    int chatter = 0, a = x->reset(t, y, x->u, x->p, k);
    *action = a;
    if (!log_room(lg, ne)) return NO_MEMORY;
    lg->ev_t[ne] = t;
    lg->ev_k[ne] = k;
    lg->ev_a[ne] = a;
    if (lg->ch_n > 0) {
        int64_t slot = ne % lg->ch_n;
        if (ne >= lg->ch_n && t - lg->ring[slot] <= lg->ch_window) chatter = 1;
        lg->ring[slot] = t;
    }
    x->stats[S_EVENTS] += 1;
    if (chatter) return CHATTER;
    if (a == A_STOP) return EVENT_STOP;
    if (a == A_FAIL) return EVENT_FAIL;
    return DONE;
}

static double locate(Ctx *x, double t, double h, double t_ref, int k, double ta, double tb,
                     double ga, double gb, double tol, double *ytmp, double *g) {
    int sign_a = ga > 0.0, side = 0, it;
    tol = pmax(tol, 4.0 * EPS * fabs(tb));
    for (it = 0; it < 200; it++) {
        double tm, gm;
        if (tb - ta <= tol) break;
        tm = tb - gb * (tb - ta) / (gb - ga);
        if (!(ta < tm && tm < tb)) tm = 0.5 * (ta + tb);
        tm = pmin(pmax(tm, ta + 0.01 * (tb - ta)), tb - 0.01 * (tb - ta));
        dense_eval(x, (tm - t) / h, ytmp);
        inputs_at(x, tm, t_ref);
        x->events(tm, ytmp, x->u, x->p, g);
        x->stats[S_EV_CALLS] += 1;
        gm = g[k];
        if (gm == 0.0 || (gm > 0.0) != sign_a) {
            tb = tm;
            gb = gm;
            if (side == 1) ga *= 0.5;
            side = 1;
        } else {
            ta = tm;
            ga = gm;
            if (side == -1) gb *= 0.5;
            side = -1;
        }
    }
    return tb;
}

static void g_at(Ctx *x, double t, double h, double t_ref, double tq, double *ytmp, double *g) {
    dense_eval(x, (tq - t) / h, ytmp);
    inputs_at(x, tq, t_ref);
    x->events(tq, ytmp, x->u, x->p, g);
    x->stats[S_EV_CALLS] += 1;
}

static void valley(Ctx *x, double t, double h, double t_ref, int k, double sigma, double lo,
                   double hi, double depth, double *ytmp, double *g, double *tq, double *fq) {
    const double r = 0.6180339887498949;
    double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1, f2;
    int it;
    g_at(x, t, h, t_ref, x1, ytmp, g);
    f1 = sigma * g[k];
    g_at(x, t, h, t_ref, x2, ytmp, g);
    f2 = sigma * g[k];
    for (it = 0; it < VALLEY_PROBES; it++) {
        if (f1 < -depth || f2 < -depth || isnan(f1) || isnan(f2)) break;
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - r * (hi - lo);
            g_at(x, t, h, t_ref, x1, ytmp, g);
            f1 = sigma * g[k];
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + r * (hi - lo);
            g_at(x, t, h, t_ref, x2, ytmp, g);
            f2 = sigma * g[k];
        }
    }
    if (f1 <= f2 || isnan(f2)) { *tq = x1; *fq = f1; }
    else { *tq = x2; *fq = f2; }
}

static void vertex(double x0, double y0, double x1, double y1, double x2, double y2,
                   double *xv, double *yv) {
    double d1 = (y1 - y0) / (x1 - x0), d2 = (y2 - y1) / (x2 - x1), a = (d2 - d1) / (x2 - x0), xx;
    if (!(a > 0.0)) { *xv = x1; *yv = INFINITY; return; }
    xx = 0.5 * (x0 + x1) - d1 / (2.0 * a);
    *xv = xx;
    *yv = y0 + d1 * (xx - x0) + a * (xx - x0) * (xx - x1);
}

/* g_samp: N_SAMPLES rows of n_ev */
static void sharpen(Ctx *x, double t, double h, double t_ref, const double *g_old,
                    double *g_samp, double *ts, int ns, double *ytmp, double *g) {
    int n_ev = x->n_ev, k, j;
#define GS(j, k) g_samp[(j) * n_ev + (k)]
    for (k = 0; k < n_ev; k++) {
        double sigma, big, x0, y0, xv, yv, b, lo, hi, depth, tq, fq;
        int low, c;
        if (g_old[k] == 0.0) continue;
        sigma = g_old[k] > 0.0 ? 1.0 : -1.0;
        low = -1;
        big = fabs(g_old[k]);
        for (j = 0; j < ns; j++) {
            big = pmax(big, fabs(GS(j, k)));
            if (!(sigma * GS(j, k) > 0.0)) { low = -2; break; }
            if (sigma * GS(j, k) < sigma * (low == -1 ? g_old[k] : GS(low, k))) low = j;
        }
        if (low == -2) continue;
        c = low > 0 ? low : 0;
        if (c > ns - 2) c = ns - 2;
        x0 = c == 0 ? t : ts[c - 1];
        y0 = sigma * (c == 0 ? g_old[k] : GS(c - 1, k));
        vertex(x0, y0, ts[c], sigma * GS(c, k), ts[c + 1], sigma * GS(c + 1, k), &xv, &yv);
        b = sigma * (low == -1 ? g_old[k] : GS(low, k));
        if (!(x0 < xv && xv < ts[c + 1] && yv <= 0.5 * b)) continue;
        lo = low <= 0 ? t : ts[low - 1];
        hi = low == ns - 1 ? ts[low] : ts[low + 1];
        depth = VALLEY_DEPTH * big;
        valley(x, t, h, t_ref, k, sigma, lo, hi, depth, ytmp, g, &tq, &fq);
        if (fq < -depth) {
            int i = low > 0 ? low : 0;
            if (i > ns - 2) i = ns - 2;
            ts[i] = tq;
            g_at(x, t, h, t_ref, tq, ytmp, g_samp + i * n_ev);
            return;
        }
    }
#undef GS
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- the loop ---- */
#define ROW(T, Y) do { \
        if (!rows_room(&R, n_out, n, n_in, n_outputs)) { status = NO_MEMORY; goto end; } \
        R.t[n_out] = (T); \
        memcpy(R.y + n_out * n, (Y), n * sizeof(double)); \
        memcpy(R.u + n_out * n_in, u, n_in * sizeof(double)); \
        memcpy(R.o + n_out * n_outputs, out, n_outputs * sizeof(double)); \
        n_out++; } while (0)

/* The step ended on a breakpoint of the inputs (at t): the next breakpoint after t is the
   next stop, and the step restarts as at a discontinuity (f0, the Jacobian and its
   factors are stale; an event may have jumped). */
#define PASS_BREAKPOINT() do { \
        ib++; \
        while (ib < n_bps && bps[ib] <= t) ib++; \
        f0_valid = 0; \
        jac_valid = 0; \
        lu_h = 0.0; \
        check_jump = 1; } while (0)

/* One run: after the plant's functions the tableau
   (a, C: s x s; c, d, m, e: s; H: nh x s), mopt, ctrl, the span, y0 (n), p, the signal
   bank's data (n_in channels), the breakpoints, the event directions (n_ev), n_outputs,
   fopt, iopt (iopt[I_STOP] is read while the loop runs: another thread sets it to stop the
   run).  Then where the results go: the caller's rows (cap of them: times, states, inputs,
   outputs) and event log (ev_cap entries), the statistics (N_STATS), res = (t_end,
   h_smallest, wall seconds, info_k, info_i), and mem = (rows owned, t, y, u, o, log owned,
   ev_t, ev_k, ev_a): where the rows and the log are at the end, and whether that is the
   engine's memory (the caller then owns it and frees each pointer with cl_free).  Returns
   the status (core.status.Code; UNSUPPORTED: the plant is larger than the engine's bounds,
   nothing was run; NO_MEMORY: a buffer could not grow, the run ended there). */
int cl_integrate(kern_t rhs, kern_t events, reset_t reset, kern_t outputs, jac_t jac,
                 fac_t factor, sol_t solve,
                 const double *a, const double *Cm, const double *c, const double *d,
                 const double *m, const double *e, const double *H, int s, int nh,
                 const double *mopt, const double *ctrl, double t0, double t1,
                 const double *y0, int n, double *p, const double *bank, int n_in,
                 const double *bps, int n_bps, const int64_t *ev_dir, int n_ev, int n_outputs,
                 const double *fopt, const volatile int64_t *iopt,
                 double *ts_out, double *ys, double *us, double *outs, int64_t cap,
                 double *ev_t, int64_t *ev_k, int64_t *ev_a, int64_t ev_cap,
                 int64_t *stats, double *res, int64_t *mem) {
    Rows R = {ts_out, ys, us, outs, cap, 0};
    Ctx X, *x = &X;
    Log LG;
    Tab TB = {a, Cm, c, d, m, e, H, s, nh};
    double y[MAXN], y_new[MAXN], ytmp[MAXN], ftmp[MAXN], f1[MAXN], err[MAXN], f0[MAXN],
        dfdt[MAXN], y_ev[MAXN], K[MAXS * MAXN], J[MAXN * MAXN], M[MAXN * MAXN], u[MAXN],
        uc[2], out[MAXOUT], F[MAXF];
    double g_old[MAXEV], g_new[MAXEV], g_prev[MAXEV], g_tmp[MAXEV], g_seg[MAXEV],
        g_pre[MAXEV], placed[MAXEV], g_samp[N_SAMPLES * MAXEV], tsamp[N_SAMPLES];
    unsigned char passes[MAXEV];
    int64_t piv[MAXN];
    int ext[MAXS + 1];
    int explicit_ = mopt[M_FAMILY] == 1.0;
    double gamma = mopt[M_GAMMA], q = mopt[M_Q];
    int dkind = (int)mopt[M_DENSE], w_method = mopt[M_W] != 0.0, fsal = mopt[M_FSAL] != 0.0;
    double rtol = fopt[O_RTOL], atol = fopt[O_ATOL];
    double h_max = fopt[O_HMAX] > 0 ? fopt[O_HMAX] : fabs(t1 - t0);
    double h_min_user = fopt[O_HMIN], wall = fopt[O_WALL], dt_out = fopt[O_DT_OUT];
    double ev_tol = fopt[O_EVENT_TOL], lu_band = w_method ? fopt[O_LU_REUSE] : 0.0;
    int64_t max_steps = iopt[I_MAX_STEPS], max_output = iopt[I_MAX_OUTPUT];
    int nd = n - (int)iopt[I_QUADRATURES], exact_jac = iopt[I_EXACT_JAC] != 0;
    int64_t jac_max_age = w_method ? iopt[I_JAC_MAX_AGE] : 0;
    int64_t n_factor = iopt[I_FACTOR_SIZE];
    int i, j, k, status = DONE, ib = 0, structured = 0, info_k = -1, info_i = -1;
    int64_t n_out = 0, jac_age = 0;
    double t = t0, h, h_smallest = INFINITY, next_out, t_right, t_wall0 = now_s();
    double lu_h = 0.0, err_old = 1.0, err_older = 1.0, h_old;
    int f0_valid, jac_valid = 0, rejected_last = 0, first = 1, last_nonfinite = -1;
    int have_history = 0, restart = 0, may_retry = 1, probes = 0, check_jump = 0;
    double t_event_stop = INFINITY;

    memset(stats, 0, N_STATS * sizeof(int64_t));
    mem[0] = mem[5] = 0;
    if (n > MAXN || s > MAXS || n_outputs > MAXOUT || n_in > MAXN || n_factor > MAXF
        || n_ev > MAXEV || iopt[I_CHATTER_N] > MAXRING || (!explicit_ && n_factor > 0 && !factor))
        return UNSUPPORTED;
    x->rhs = rhs; x->events = events; x->outputs = outputs; x->reset = reset; x->jac = jac;
    x->factor = factor; x->solve = solve; x->bank = bank; x->p = p; x->u = u; x->uc = uc;
    x->stats = stats; x->n = n; x->nd = nd; x->n_ev = n_ev; x->dkind = dkind;
    LG.ev_t = ev_t; LG.ev_k = ev_k; LG.ev_a = ev_a; LG.cap = ev_cap; LG.owned = 0;
    LG.ch_n = iopt[I_CHATTER_N]; LG.ch_window = fopt[O_CHATTER_WINDOW];
    for (i = 0; i < (LG.ch_n > 1 ? LG.ch_n : 1); i++) LG.ring[i] = -INFINITY;
    memset(J, 0, sizeof J);
    memset(M, 0, sizeof M);
    memset(K, 0, sizeof K);
    memset(x->dense, 0, sizeof x->dense);
    for (i = 0; i < n; i++) y[i] = y0[i];
    uc[0] = uc[1] = NAN;
    for (k = 0; k < n_ev; k++) passes[k] = 0;
    /* stiffly_accurate_rows */
    for (j = 0; j <= s; j++) ext[j] = 0;
    if (!explicit_)
        for (j = 2; j <= s; j++) {
            int row_is_m = j == s, same = 1, jj;
            if ((row_is_m ? m[s - 1] : a[j * s + j - 1]) != 1.0) continue;
            for (jj = 0; jj < j - 1; jj++)
                if ((row_is_m ? m[jj] : a[j * s + jj]) != a[(j - 1) * s + jj]) { same = 0; break; }
            if (same) ext[j] = 1;
        }
    while (ib < n_bps && bps[ib] <= t0) ib++;

    t_right = t + 1e-300 + 1e-12 * fabs(t);
    inputs_at(x, t, t_right);
    rhs(t, y, u, p, f0);
    stats[S_RHS] += 1;
    events(t, y, u, p, g_old);
    outputs(t, y, u, p, out);
    ROW(t, y);
    next_out = t0 + dt_out;
    {
        int bad = first_nonfinite(f0, n), iy = first_nonfinite(y, n);
        if (iy >= 0 || bad >= 0) {
            status = NON_FINITE;
            info_i = iy >= 0 ? iy : bad;
            goto end;
        }
    }
    h = fopt[O_H0];
    if (h <= 0) h = starting_step(x, t, y, f0, ytmp, ftmp, atol, rtol, q, h_max);
    f0_valid = 1;
    h_old = h;
    for (k = 0; k < n_ev; k++) {
        if ((ev_dir[k] == -1 && g_old[k] < 0.0) || (ev_dir[k] == 1 && g_old[k] > 0.0)) {
            g_old[k] = -g_old[k];
            check_jump = 1;
        }
        placed[k] = g_old[k] == 0.0 ? 1.0 : 0.0;
    }

    for (;;) {
        double t_stop, h_floor, t_ref, en, t_new, fac, h_next;
        int hit, ok, stop_at_event, sample;
        if (check_jump) {
            int kk = -1;
            check_jump = 0;
            have_history = 0;
            t_right = t + 1e-300 + 1e-12 * fabs(t);
            inputs_at(x, t, t_right);
            events(t, y, u, p, g_new);
            stats[S_EV_CALLS] += 1;
            for (k = 0; k < n_ev; k++)
                if (crossed(g_old[k], g_new[k], ev_dir[k])) { kk = k; break; }
            if (kk < 0) {
                double tiny = round_off(y, n);
                for (k = 0; k < n_ev; k++)
                    if (!(placed[k] != 0.0 && g_old[k] == 0.0 && fabs(g_new[k]) <= tiny))
                        g_old[k] = g_new[k];
            } else {
                int action, ended = apply_event(x, &LG, t, y, kk, &action);
                if (ended != DONE) { status = ended; info_k = kk; break; }
                if (action == A_STATE_CHANGED) {
                    f0_valid = 0;
                    jac_valid = 0;
                    lu_h = 0.0;
                    events(t, y, u, p, g_tmp);
                    place(g_new, g_tmp, y, n, n_ev, placed);
                    outputs(t, y, u, p, out);
                    ROW(t, y);
                } else {
                    for (k = 0; k < n_ev; k++) { g_tmp[k] = g_new[k]; placed[k] = 0.0; }
                }
                for (k = 0; k < n_ev; k++) {
                    if (k != kk && crossed(g_old[k], g_new[k], ev_dir[k])
                        && crossed(g_old[k], g_tmp[k], ev_dir[k]))
                        check_jump = 1;
                    else g_old[k] = g_tmp[k];
                }
                if (action == A_STATE_CHANGED) check_jump = 1;
                continue;
            }
        }
        if (t >= t1) break;
        if (stats[S_STEPS] + stats[S_REJECTED] >= max_steps) { status = MAX_STEPS; break; }
        if (((stats[S_STEPS] + stats[S_REJECTED]) & 255) == 0
            && (iopt[I_STOP] != 0 || (wall > 0 && now_s() - t_wall0 > wall))) {
            status = WALL_TIME;
            break;
        }
        t_stop = t1;
        if (ib < n_bps && bps[ib] < t1) t_stop = bps[ib];
        h_floor = pmax(h_min_user, 1e-14 * pmax(1.0, fabs(t)));
        if (t_event_stop - t <= h_floor) t_event_stop = INFINITY;
        stop_at_event = t_event_stop < t_stop;
        if (stop_at_event) t_stop = t_event_stop;
        if (t_stop - t <= h_floor) {
            t = t_stop;
            if (t_stop < t1) PASS_BREAKPOINT();
            continue;
        }
        if (restart) {
            restart = 0;
            inputs_at(x, t, t + 0.5 * pmin(h, t_stop - t));
            rhs(t, y, u, p, f0);
            stats[S_RHS] += 1;
            f0_valid = first_nonfinite(f0, n) < 0;
            if (f0_valid) h = pmin(h, starting_step(x, t, y, f0, ytmp, ftmp, atol, rtol, q, h_max));
        }
        hit = 0;
        h = pmin(h, h_max);
        if (t + h >= t_stop - h_floor) { h = t_stop - t; hit = 1; }
        else if (t + 2.0 * h > t_stop) h = 0.5 * (t_stop - t);
        if (h < h_floor) {
            status = last_nonfinite >= 0 ? NON_FINITE : STEP_COLLAPSE;
            info_i = last_nonfinite;
            break;
        }
        t_ref = t + 0.5 * h;
        if (!f0_valid) {
            int bad;
            inputs_at(x, t, t_ref);
            rhs(t, y, u, p, f0);
            stats[S_RHS] += 1;
            f0_valid = 1;
            bad = first_nonfinite(f0, n);
            if (bad >= 0) { status = NON_FINITE; info_i = bad; break; }
        }
        ok = 1;
        if (explicit_) {
            for (i = 0; i < n; i++) K[i] = f0[i];
            stats[S_RHS] += erk_step(x, t, y, h, t_ref, K, ytmp, y_new, err, &TB);
        } else {
            if (!jac_valid) {
                stats[S_RHS] += jacobian(x, t, y, t_ref, f0, atol / rtol, ytmp, ftmp, J, dfdt,
                                         exact_jac);
                stats[S_JAC] += 1;
                jac_valid = 1;
                jac_age = 0;
                lu_h = 0.0;
                if (exact_jac && !all_finite(J, n * n)) {
                    for (i = 0; i < n; i++) {
                        int bad = first_nonfinite(J + i * n, n);
                        if (bad >= 0) { last_nonfinite = bad; break; }
                    }
                    if (last_nonfinite >= 0) {
                        status = JAC_NON_FINITE;
                        info_i = last_nonfinite;
                        break;
                    }
                }
            }
            if (lu_h == 0.0 || fabs(h / lu_h - 1.0) > lu_band) {
                double cc = 1.0 / (gamma * h);
                structured = n_factor > 0 && factor(cc, J, n, F) != 0;
                ok = structured || invert(J, cc, M, piv, n, nd);
                stats[S_LU] += 1;
                lu_h = ok ? h : 0.0;
            }
            if (ok)
                stats[S_RHS] += ros_step(x, t, y, h, t_ref, f0, dfdt, M, F, structured, K,
                                         ytmp, ftmp, y_new, err, &TB, ext);
        }
        if (ok) {
            int bad = -1;
            if (!(all_finite(y_new, n) && all_finite(err, n))) {
                bad = first_nonfinite(y_new, n);
                if (bad < 0) bad = first_nonfinite(err, n);
            }
            if (bad >= 0) {
                int culprit;
                inputs_at(x, t + h, t_ref);
                rhs(t + h, y, u, p, ftmp);
                stats[S_RHS] += 1;
                culprit = first_nonfinite(ftmp, n);
                if (culprit < 0 && !explicit_) {
                    culprit = first_nonfinite(dfdt, n);
                    for (i = 0; i < n; i++) {
                        if (culprit >= 0) break;
                        if (first_nonfinite(J + i * n, n) >= 0) culprit = i;
                    }
                }
                last_nonfinite = culprit >= 0 ? culprit : bad;
                ok = 0;
            }
        }
        if (!ok) {
            stats[S_REJECTED] += 1;
            h *= 0.25;
            rejected_last = 1;
            if (jac_age > 0) jac_valid = 0;
            lu_h = 0.0;
            continue;
        }
        en = norm(err, y, y_new, n, rtol, atol);
        if (en > 1.0) {
            stats[S_REJECTED] += 1;
            h *= pmax(ctrl[C_MIN], ctrl[C_SAFETY] * pow(en, -1.0 / q));
            rejected_last = 1;
            if (jac_age > 0) jac_valid = 0;
            lu_h = 0.0;
            continue;
        }
        t_new = hit ? t_stop : t + h;
        if (explicit_ && fsal) {
            for (i = 0; i < n; i++) f1[i] = K[(s - 1) * n + i];
        } else {
            int bad;
            inputs_at(x, t_new, t_ref);
            rhs(t_new, y_new, u, p, f1);
            stats[S_RHS] += 1;
            bad = all_finite(f1, n) ? -1 : first_nonfinite(f1, n);
            if (bad >= 0) {
                last_nonfinite = bad;
                stats[S_REJECTED] += 1;
                h *= 0.25;
                rejected_last = 1;
                lu_h = 0.0;
                continue;
            }
        }
        /* ---- accepted ---- */
        last_nonfinite = -1;
        stats[S_STEPS] += 1;
        h_smallest = pmin(h_smallest, h);
        if (w_method) jac_age++;
        fac = controller_factor(ctrl, q, en, err_old, err_older, h, h_old, first);
        h_next = h * fac;
        if (rejected_last) h_next = pmin(h_next, h);
        h_old = h;
        err_older = err_old;
        err_old = ctrl[C_KIND] == 1.0 ? pmax(0.01, en) : pmax(en, 1e-10);
        first = 0;
        rejected_last = 0;

        /* ---- events inside the step ---- */
        sample = 0;
        if (n_ev > 0) {
            inputs_at(x, t_new, t_ref);
            events(t_new, y_new, u, p, g_new);
            stats[S_EV_CALLS] += 1;
            sample = !have_history;
            for (k = 0; k < n_ev; k++) {
                if (sample) break;
                sample = g_old[k] == 0.0 || ((g_old[k] > 0.0) != (g_new[k] > 0.0))
                    || may_hide_crossing(g_prev[k], g_old[k], g_new[k]);
            }
        }
        if (sample || (dt_out > 0 && next_out <= t_new + 1e-12 * fabs(t_new) && n_out < max_output))
            dense_coefficients(x, &TB, K, s > 1 ? s : 1, y, y_new, f0, f1, h);
        if (n_ev > 0) {
            int ns = sample ? N_SAMPLES : 1, ended = DONE, action = A_PASS, retry = 0, pending = 0;
            int k_first = -1;
            double t_seg, te = t_new;
            if (sample)
                for (j = 0; j < ns - 1; j++) {
                    double sf = (j + 1.0) / ns;
                    tsamp[j] = t + sf * h;
                    dense_eval(x, sf, ytmp);
                    inputs_at(x, t + sf * h, t_ref);
                    events(t + sf * h, ytmp, u, p, g_samp + j * n_ev);
                    stats[S_EV_CALLS] += 1;
                }
            tsamp[ns - 1] = t_new;
            for (k = 0; k < n_ev; k++) {
                g_samp[(ns - 1) * n_ev + k] = g_new[k];
                g_seg[k] = g_old[k];
            }
            if (sample) sharpen(x, t, h, t_ref, g_old, g_samp, tsamp, ns, ytmp, g_tmp);
            t_seg = t;
            for (;;) {
                double t_first = t_new;
                k_first = -1;
                for (k = 0; k < n_ev; k++) {
                    double ga = g_seg[k], ta = t_seg;
                    for (j = 0; j < ns; j++) {
                        double tb = tsamp[j], gb;
                        if (tb <= t_seg) continue;
                        gb = g_samp[j * n_ev + k];
                        if (ga == 0.0) {
                            if (placed[k] != 0.0 && ev_dir[k] * gb > 0.0) {
                                if (k_first < 0 || ta < t_first) { t_first = ta; k_first = k; }
                                break;
                            }
                            ga = gb;
                            ta = tb;
                            continue;
                        }
                        if (crossed(ga, gb, ev_dir[k])) {
                            if (ta >= t_first && k_first >= 0) break;
                            te = locate(x, t, h, t_ref, k, ta, tb, ga, gb, ev_tol, ytmp, g_tmp);
                            if (k_first < 0 || te < t_first) { t_first = te; k_first = k; }
                            break;
                        }
                        if (gb != 0.0) { ga = gb; ta = tb; }
                    }
                }
                if (k_first < 0) break;
                te = t_first;
                if (te == t && t_seg == t && placed[k_first] != 0.0 && probes < MAX_PROBES
                    && PROBE * h > 1e3 * h_floor) {
                    retry = 1;
                    break;
                }
                if (may_retry && !passes[k_first] && t_seg == t && te < t_new
                    && te - t > pmax(1e-3 * h, 1e3 * h_floor)) {
                    retry = 1;
                    break;
                }
                if (te < t_new) dense_eval(x, (te - t) / h, y_ev);
                else for (i = 0; i < n; i++) y_ev[i] = y_new[i];
                if (dt_out > 0)
                    while (next_out < te && n_out < max_output) {
                        dense_eval(x, (next_out - t) / h, ytmp);
                        inputs_at(x, next_out, t_ref);
                        outputs(next_out, ytmp, u, p, out);
                        ROW(next_out, ytmp);
                        next_out = t0 + (nearbyint((next_out - t0) / dt_out) + 1) * dt_out;
                    }
                inputs_at(x, te, t_ref);
                outputs(te, y_ev, u, p, out);
                ROW(te, y_ev);
                events(te, y_ev, u, p, g_pre);
                ended = apply_event(x, &LG, te, y_ev, k_first, &action);
                if (ended == NO_MEMORY) { status = NO_MEMORY; goto end; }
                passes[k_first] = action == A_PASS;
                for (k = 0; k < n_ev; k++) g_tmp[k] = g_seg[k];
                events(te, y_ev, u, p, g_seg);
                stats[S_EV_CALLS] += 2;
                place(g_pre, g_seg, y_ev, n, n_ev, placed);
                pending = 0;
                for (k = 0; k < n_ev; k++)
                    if (k != k_first && g_tmp[k] != 0.0 && crossed(g_tmp[k], g_pre[k], ev_dir[k])
                        && crossed(g_tmp[k], g_seg[k], ev_dir[k])) {
                        g_seg[k] = g_tmp[k];
                        pending = 1;
                    }
                if (ended != DONE || action != A_PASS) break;
                t_seg = te;
            }
            if (retry) {
                stats[S_STEPS] -= 1;
                stats[S_REJECTED] += 1;
                if (te == t) {
                    probes++;
                    h = PROBE * h;
                    continue;
                }
                may_retry = 0;
                t_event_stop = te;
                h = te - t;
                continue;
            }
            probes = 0;
            if (k_first >= 0) {
                may_retry = 1;
                t_event_stop = INFINITY;
            }
            if (k_first >= 0 && ended != DONE) {
                status = ended;
                info_k = k_first;
                break;
            }
            if (k_first >= 0) {
                t = te;
                for (i = 0; i < n; i++) y[i] = y_ev[i];
                for (k = 0; k < n_ev; k++) g_old[k] = g_seg[k];
                have_history = 0;
                f0_valid = 0;
                restart = 1;
                if (!w_method) jac_valid = 0;
                if (action == A_STATE_CHANGED) {
                    outputs(t, y, u, p, out);
                    ROW(t, y);
                    check_jump = 1;
                }
                if (pending) check_jump = 1;
                h = h_next;
                continue;
            }
        }
        /* ---- no event: advance ---- */
        if (dt_out > 0) {
            while (next_out <= t_new + 1e-12 * fabs(t_new) && n_out < max_output) {
                double tq = pmin(next_out, t_new);
                dense_eval(x, (tq - t) / h, ytmp);
                inputs_at(x, tq, t_ref);
                outputs(tq, ytmp, u, p, out);
                ROW(tq, ytmp);
                next_out = t0 + (nearbyint((next_out - t0) / dt_out) + 1) * dt_out;
            }
        } else if (n_out < max_output) {
            inputs_at(x, t_new, t_ref);
            outputs(t_new, y_new, u, p, out);
            ROW(t_new, y_new);
        }
        t = t_new;
        for (i = 0; i < n; i++) { y[i] = y_new[i]; f0[i] = f1[i]; }
        for (k = 0; k < n_ev; k++) {
            g_prev[k] = g_old[k];
            g_old[k] = g_new[k];
            placed[k] = 0.0;
        }
        have_history = 1;
        if (!w_method || jac_age >= jac_max_age) jac_valid = 0;
        h = h_next;
        if (hit && t_stop < t1 && !stop_at_event) PASS_BREAKPOINT();
    }
    if (dt_out > 0 && status == DONE && n_out < max_output && R.t[n_out - 1] < t) {
        inputs_at(x, t, t);
        outputs(t, y, u, p, out);
        ROW(t, y);
    }
end:
    mem[0] = R.owned;
    mem[1] = (int64_t)(intptr_t)R.t;
    mem[2] = (int64_t)(intptr_t)R.y;
    mem[3] = (int64_t)(intptr_t)R.u;
    mem[4] = (int64_t)(intptr_t)R.o;
    mem[5] = LG.owned;
    mem[6] = (int64_t)(intptr_t)LG.ev_t;
    mem[7] = (int64_t)(intptr_t)LG.ev_k;
    mem[8] = (int64_t)(intptr_t)LG.ev_a;
    stats[S_OUTPUT] = n_out;
    res[0] = t;
    res[1] = h_smallest;
    res[2] = now_s() - t_wall0;
    res[3] = info_k;
    res[4] = info_i;
    return status;
}

/* The bank's first channel at each of the n_t times t into out (Signal.__call__; numba's
   _eval_series in core/signals.py where there is no engine): u is the caller's room for
   the bank's channels, at least one */
void cl_eval_series(const double *bank, int n_t, const double *t, double *u, double *out) {
    int i;
    for (i = 0; i < n_t; i++) {
        eval_inputs(bank, t[i], t[i], u);
        out[i] = u[0];
    }
}

/* Memory of the engine's own that a run handed over (cl_integrate's mem) */
void cl_free(void *ptr) { free(ptr); }

/* cl_integrate for a caller in numba (clutchsim.analysis.launch_batch): every integer and
   pointer as a 64-bit integer, the calling convention of a numba function value whose
   arguments are all scalars (clutchsim.core.cengine.EngineFunction) */
int64_t cl_integrate_nb(int64_t rhs, int64_t events, int64_t reset, int64_t outputs,
                        int64_t jac, int64_t factor, int64_t solve, int64_t a, int64_t Cm,
                        int64_t c, int64_t d, int64_t m, int64_t e, int64_t H, int64_t s,
                        int64_t nh, int64_t mopt, int64_t ctrl, double t0, double t1,
                        int64_t y0, int64_t n, int64_t p, int64_t bank, int64_t n_in,
                        int64_t bps, int64_t n_bps, int64_t ev_dir, int64_t n_ev,
                        int64_t n_outputs, int64_t fopt, int64_t iopt, int64_t ts_out,
                        int64_t ys, int64_t us, int64_t outs, int64_t cap, int64_t ev_t,
                        int64_t ev_k, int64_t ev_a, int64_t ev_cap, int64_t stats,
                        int64_t res, int64_t mem) {
#define PTR(T, x) ((T)(intptr_t)(x))
    return cl_integrate(PTR(kern_t, rhs), PTR(kern_t, events), PTR(reset_t, reset),
                        PTR(kern_t, outputs), PTR(jac_t, jac), PTR(fac_t, factor),
                        PTR(sol_t, solve), PTR(const double *, a), PTR(const double *, Cm),
                        PTR(const double *, c), PTR(const double *, d), PTR(const double *, m),
                        PTR(const double *, e), PTR(const double *, H), (int)s, (int)nh,
                        PTR(const double *, mopt), PTR(const double *, ctrl), t0, t1,
                        PTR(const double *, y0), (int)n, PTR(double *, p),
                        PTR(const double *, bank), (int)n_in, PTR(const double *, bps),
                        (int)n_bps, PTR(const int64_t *, ev_dir), (int)n_ev, (int)n_outputs,
                        PTR(const double *, fopt), PTR(const volatile int64_t *, iopt),
                        PTR(double *, ts_out), PTR(double *, ys), PTR(double *, us),
                        PTR(double *, outs), cap, PTR(double *, ev_t), PTR(int64_t *, ev_k),
                        PTR(int64_t *, ev_a), ev_cap, PTR(int64_t *, stats),
                        PTR(double *, res), PTR(int64_t *, mem));
#undef PTR
}

/* cl_free for a caller in numba (a function value of one 64-bit integer) */
void cl_free_nb(int64_t ptr) { free((void *)(intptr_t)ptr); }

/* The dense inverse of the leading nd x nd block of c·I − J (n x n, the rest the
   quadratures' diagonal; returns 0 where a pivot is zero or NaN) and a stage solve with it
   into row r of X (rows of n), as a step makes them: for the tests of the linear algebra
   and benchmarks/step_cost.py.  Pointers and integers as 64-bit integers (a numba function
   value of scalars, as cl_integrate_nb). */
int64_t cl_invert_nb(int64_t J, double c, int64_t M, int64_t piv, int64_t n, int64_t nd) {
    return invert((const double *)(intptr_t)J, c, (double *)(intptr_t)M,
                  (int64_t *)(intptr_t)piv, (int)n, (int)nd);
}

void cl_solve_into_row_nb(int64_t M, int64_t b, int64_t X, int64_t r, int64_t n, int64_t nd) {
    solve_into_row((const double *)(intptr_t)M, (const double *)(intptr_t)b,
                   (double *)(intptr_t)X, (int)r, (int)n, (int)nd);
}
