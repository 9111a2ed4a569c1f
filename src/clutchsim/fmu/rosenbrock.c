/* The co-simulation solver of a clutchsim FMU (clutchsim/fmu/rosenbrock.c), included by
   the FMI glue after plant_core.c.

   The inputs are held over a communication step, or, where the importer gives their
   first derivatives (FMI 2 canInterpolateInputs, fmi2SetRealInputDerivatives), follow
   u + du·(t − t_step) within it: an importer's piecewise-linear input is then followed
   as the native run follows it, where held inputs lag a ramp by half a step.  Events: after
   each accepted step the indicators are compared with the step's start; a crossing in
   the plant's direction is located by bisection on the step (each probe one ROS2 step from
   the step's start) to 1e-12 s, the state is placed just past it, and the core applies
   the reset as in Model Exchange (core_event). */

#include "ros2.c"

/* The inputs at time t of the communication step (held without derivatives) */
static void rb_inputs(Instance *m, double t) {
    int i;
    if (!m->has_du) return;
    for (i = 0; i < CS_NU; i++) m->u[i] = m->u_step[i] + m->du[i] * (t - m->t_step);
}

/* One ROS2 step of the instance's plant (ros2.c) from t, its inputs following their
   derivatives */
static int rb_step(Instance *m, double t, const double *y0, double h, double *y1, double *err) {
    rb_inputs(m, t);
    return ros2_step(t, y0, m->u, m->has_du ? m->du : NULL, m->p, h, y1, err);
}

/* Place the instance at time t with state y (the inputs at t) */
static void rb_place(Instance *m, double t, const double *y) {
    m->t = t;
    memcpy(m->y, y, sizeof m->y);
    rb_inputs(m, t);
    changed(m);
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
            rb_place(m, t0 + h, y1);
            indicators(m, gb);
            if (rb_crossing(m, ga, gb)) {
                double lo = 0.0, hi = h, yh[N];
                int it;
                memcpy(yh, y1, sizeof yh);
                for (it = 0; it < 200 && hi - lo > 1e-12 * (1.0 + fabs(t0)); it++) {
                    double mid = 0.5 * (lo + hi), ym[N], gm[Z];
                    rb_step(m, t0, y0, mid, ym, err);
                    rb_place(m, t0 + mid, ym);
                    indicators(m, gm);
                    if (rb_crossing(m, ga, gm)) { hi = mid; memcpy(yh, ym, sizeof yh); }
                    else lo = mid;
                }
                rb_place(m, t0 + hi, yh);
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

/* Fixed steps of CS_FIXED_STEP from m->t to t_end (an FMU exported with a fixed step, as the
   real-time kernel rt_kernel.c takes them): one ROS2 step, then the events due at its end,
   not located (core_event); the status. */
static int rb_fixed(Instance *m, double t_end) {
    enum { N = ONE(CS_NX), Z = ONE(CS_NZ) };
    double y1[N], err[N], g[Z], t0 = m->t, span = t_end - m->t;
    long k, n = lround(span / CS_FIXED_STEP);
    if (n < 1 || fabs(n * CS_FIXED_STEP - span) > 1e-9 * (1.0 + fabs(t_end))) {
        logf_(m, ST_ERROR, "error", "t = %.9g s: the communication step %.9g s is not a "
              "multiple of the FMU's fixed step %.9g s", m->t, span, CS_FIXED_STEP);
        return ST_ERROR;
    }
    for (k = 1; k <= n; k++) {
        int j;
        if (!rb_step(m, m->t, m->y, CS_FIXED_STEP, y1, err)) {
            logf_(m, ST_ERROR, "error", "t = %.9g s: the fixed step failed (a singular "
                  "matrix or a value that is not finite)", m->t);
            return ST_ERROR;
        }
        rb_place(m, k == n ? t_end : t0 + k * CS_FIXED_STEP, y1);
        indicators(m, g);
        if (rb_crossing(m, m->g_last, g)) {
            int vc, term, st = core_event(m, &vc, &term);
            if (term) return st == ST_OK ? ST_DISCARD : st;
            continue;
        }
        for (j = 0; j < CS_NZ; j++)          /* one on zero keeps its sign (the core's rule) */
            if (g[j] != 0.0) m->g_last[j] = g[j];
    }
    return ST_OK;
}

/* The end of a communication step: the input derivatives served this step only (the
   importer gives them again with the next step's inputs); the inputs stay at their
   values at the step's end */
static int rb_step_done(Instance *m, int status) {
    memset(m->du, 0, sizeof m->du);
    m->has_du = 0;
    return status;
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
    memcpy(m->u_step, m->u, sizeof m->u_step);
    m->t_step = m->t;
    indicators(m, g);
    if (rb_crossing(m, m->g_last, g)) {
        int vc, term, st = core_event(m, &vc, &term);
        if (term) return rb_step_done(m, st == ST_OK ? ST_DISCARD : st);
    }
    if (CS_FIXED_STEP > 0.0) return rb_step_done(m, rb_fixed(m, t + h));
    return rb_step_done(m, rb_integrate(m, t + h, m->rtol, 1e-2 * m->rtol, &m->h));
}
