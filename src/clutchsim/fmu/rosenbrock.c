/* The co-simulation solver of a clutchsim FMU (clutchsim/fmu/rosenbrock.c), included by
   the FMI glue after plant_core.c.

   ROS2 (Verwer, Spee, Blom, Hundsdorfer 1999: "A second-order Rosenbrock method applied to
   photochemical dispersion problems", SIAM J. Sci. Comput. 20(4)), L-stable, with the
   plant's exact Jacobian (cs_jac) and its embedded first-order solution for the error:

       (I - g h J) k1 = f(y)
       (I - g h J) k2 = f(y + h k1) - 2 k1,          g = 1 + 1/sqrt(2)
       y1 = y + 3/2 h k1 + 1/2 h k2,                  error = y1 - (y + h k1)

   The inputs are held over a communication step (FMI co-simulation without input
   derivatives), so the right-hand side does not depend on time within it.  Events: after
   each accepted step the indicators are compared with the step's start; a crossing in
   the plant's direction is located by bisection on the step (each probe one ROS2 step from
   the step's start) to 1e-12 s, the state is placed just past it, and the core applies
   the reset as in Model Exchange (core_event). */

#define RB_G 1.7071067811865475     /* 1 + 1/sqrt(2) */

/* LU with partial pivoting of the n x n row-major a, in place; 0 if singular */
static int rb_lu(double *a, int *piv, int n) {
    int i, j, k;
    for (k = 0; k < n; k++) {
        int pk = k;
        double big = fabs(a[k * n + k]);
        for (i = k + 1; i < n; i++)
            if (fabs(a[i * n + k]) > big) { big = fabs(a[i * n + k]); pk = i; }
        if (big == 0.0) return 0;
        piv[k] = pk;
        if (pk != k)
            for (j = 0; j < n; j++) { double s = a[k * n + j]; a[k * n + j] = a[pk * n + j]; a[pk * n + j] = s; }
        for (i = k + 1; i < n; i++) {
            double f = a[i * n + k] / a[k * n + k];
            a[i * n + k] = f;
            for (j = k + 1; j < n; j++) a[i * n + j] -= f * a[k * n + j];
        }
    }
    return 1;
}

static void rb_solve(const double *a, const int *piv, int n, double *b) {
    int i, j;
    for (i = 0; i < n; i++) {
        double s;
        if (piv[i] != i) { s = b[i]; b[i] = b[piv[i]]; b[piv[i]] = s; }
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < i; j++) b[i] -= a[i * n + j] * b[j];
    for (i = n - 1; i >= 0; i--) {
        for (j = i + 1; j < n; j++) b[i] -= a[i * n + j] * b[j];
        b[i] /= a[i * n + i];
    }
}

/* One ROS2 step of size h from (t, y0) into y1 (and the error into err); 0 if the matrix
   is singular or a value is not finite */
static int rb_step(Instance *m, double t, const double *y0, double h, double *y1, double *err) {
    enum { N = ONE(CS_NX) };
    double J[N * N], A[N * N], k1[N], k2[N], yt[N], f[N];
    int piv[N], i, j, n = CS_NX;
    memcpy(yt, y0, sizeof yt);
    memset(J, 0, sizeof J);
    cs_jac(t, yt, m->u, m->p, J, n);
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) A[i * n + j] = (i == j ? 1.0 : 0.0) - RB_G * h * J[i * n + j];
    if (!rb_lu(A, piv, n)) return 0;
    memset(k1, 0, sizeof k1);
    cs_rhs(t, yt, m->u, m->p, k1);
    rb_solve(A, piv, n, k1);
    for (i = 0; i < n; i++) yt[i] = y0[i] + h * k1[i];
    memset(f, 0, sizeof f);
    cs_rhs(t + h, yt, m->u, m->p, f);
    for (i = 0; i < n; i++) k2[i] = f[i] - 2.0 * k1[i];
    rb_solve(A, piv, n, k2);
    for (i = 0; i < n; i++) {
        y1[i] = y0[i] + 1.5 * h * k1[i] + 0.5 * h * k2[i];
        err[i] = 0.5 * h * (k1[i] + k2[i]);
        if (!isfinite(y1[i])) return 0;
    }
    return 1;
}

static double rb_norm(const double *y0, const double *y1, const double *err, double rtol, double atol) {
    double s = 0.0;
    int i;
    for (i = 0; i < CS_NX; i++) {
        double sc = atol + rtol * fmax(fabs(y0[i]), fabs(y1[i]));
        s += (err[i] / sc) * (err[i] / sc);
    }
    return CS_NX > 0 ? sqrt(s / CS_NX) : 0.0;
}

static int rb_crossing(Instance *m, const double *ga, const double *gb) {
    int k;
    for (k = 0; k < CS_NZ; k++)
        if (crossed(cs_event_dir[k], ga[k], gb[k])) return 1;
    return 0;
}

/* Integrate the instance from m->t to t_end (inputs held), handling events; the status. */
static int rb_integrate(Instance *m, double t_end, double rtol, double atol, double *h_io) {
    enum { N = ONE(CS_NX), Z = ONE(CS_NZ) };
    double y1[N], err[N], ga[Z], gb[Z], h = *h_io;
    long steps = 0;
    while (m->t < t_end) {
        double e;
        int ok;
        if (h > t_end - m->t) h = t_end - m->t;
        if (++steps > 10000000L) {
            logf_(m, ST_ERROR, "error", "t = %.9g s: more than 1e7 steps in one communication step", m->t);
            return ST_ERROR;
        }
        ok = rb_step(m, m->t, m->y, h, y1, err);
        e = ok ? rb_norm(m->y, y1, err, rtol, atol) : 1e300;
        if (e > 1.0) {
            h *= ok ? fmax(0.2, 0.9 / sqrt(e)) : 0.25;
            if (h < 1e-14 * (1.0 + fabs(m->t))) {
                logf_(m, ST_ERROR, "error", "t = %.9g s: the step size collapsed", m->t);
                return ST_ERROR;
            }
            continue;
        }
        /* events inside the accepted step */
        memcpy(ga, m->g_last, sizeof ga);
        {
            double t0 = m->t, y0[N];
            memcpy(y0, m->y, sizeof y0);
            m->t = t0 + h;
            memcpy(m->y, y1, sizeof y0);
            changed(m);
            indicators(m, gb);
            if (rb_crossing(m, ga, gb)) {
                double lo = 0.0, hi = h, yh[N];
                int it;
                memcpy(yh, y1, sizeof yh);
                for (it = 0; it < 200 && hi - lo > 1e-12 * (1.0 + fabs(t0)); it++) {
                    double mid = 0.5 * (lo + hi), ym[N], gm[Z];
                    rb_step(m, t0, y0, mid, ym, err);
                    m->t = t0 + mid;
                    memcpy(m->y, ym, sizeof ym);
                    changed(m);
                    indicators(m, gm);
                    if (rb_crossing(m, ga, gm)) { hi = mid; memcpy(yh, ym, sizeof yh); }
                    else lo = mid;
                }
                m->t = t0 + hi;
                memcpy(m->y, yh, sizeof yh);
                changed(m);
                {
                    int vc, term, st = core_event(m, &vc, &term);
                    if (term) { *h_io = h; return st == ST_OK ? ST_DISCARD : st; }
                }
                h = fmax(h * 0.1, 1e-10);     /* restart gently past the switch */
                continue;
            }
            memcpy(m->g_last, gb, sizeof gb);
            /* keep an indicator that sits on zero on its next sign (the core's rule) */
            {
                int k;
                for (k = 0; k < CS_NZ; k++)
                    if (gb[k] == 0.0) m->g_last[k] = ga[k];
            }
        }
        h *= fmin(5.0, fmax(0.2, 0.9 / sqrt(fmax(e, 1e-10))));
    }
    *h_io = h;
    return ST_OK;
}

/* One communication step from t to t + h (fmi2DoStep, fmi3DoStep): an event at the
   communication point first (the start's directional events, an input jump), then the
   integration with its events; the status (ST_DISCARD: a terminal stop ended the run at
   m->t). */
static int rb_do_step(Instance *m, double t, double h, const char *fn) {
    double g[ONE(CS_NZ)];
    if (!CS_COSIM || !m->cosim) {
        logf_(m, ST_ERROR, "error", "%s: the instance is not for co-simulation", fn);
        return ST_ERROR;
    }
    if (fabs(t - m->t) > 1e-9 * (1.0 + fabs(t))) {
        logf_(m, ST_ERROR, "error", "%s: communication point %.17g s, but the FMU is at %.17g s", fn, t, m->t);
        return ST_ERROR;
    }
    m->mode = MODE_CONT;
    indicators(m, g);
    if (rb_crossing(m, m->g_last, g)) {
        int vc, term, st = core_event(m, &vc, &term);
        if (term) return st == ST_OK ? ST_DISCARD : st;
    }
    return rb_integrate(m, t + h, m->rtol, 1e-2 * m->rtol, &m->h);
}
