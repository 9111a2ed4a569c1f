/* The fixed-step real-time kernel of clutchsim (clutchsim/fmu/rt_kernel.c); see
   clutchsim_rt.h.  Compiled with the printed plant (plant.c) and its layout (model.h). */

#include <math.h>
#include <string.h>

#include "clutchsim_rt.h"

void cs_rhs(double t, double *y, double *u, double *p, double *dy);
void cs_outputs(double t, double *y, double *u, double *p, double *out);
void cs_events(double t, double *y, double *u, double *p, double *g);
int cs_reset(double t, double *y, double *u, double *p, int k);
void cs_jac(double t, double *y, double *u, double *p, double *J, int J_nc);

#define ONE(n) CS_RT_ONE(n)
#include "ros2.c"

/* the reset map's actions (clutchsim.core.status.Action) */
enum { RT_CONTINUE = 0, RT_STATE_CHANGED = 1, RT_STOP = 2, RT_FAIL = 3, RT_PASS = 4 };

static int rt_crossed(int dir, double before, double now) {
    /* clutchsim.core._driver._crossed */
    return (dir >= 0 && before < 0.0 && now >= 0.0) || (dir <= 0 && before > 0.0 && now <= 0.0);
}

void cs_rt_init(cs_rt_instance *s) {
    int k;
    memset(s, 0, sizeof *s);
    memcpy(s->y, cs_y0, sizeof s->y);
    memcpy(s->u, cs_u0, sizeof s->u);
    memcpy(s->p, cs_p0, sizeof s->p);
    s->stopped_by = -1;
    if (CS_NZ > 0) cs_events(0.0, s->y, s->u, s->p, s->g);
    /* a directional event whose function starts on its far side fires in the first step
       (a stuck element loaded beyond its capacity), as in clutchsim's integrators */
    for (k = 0; k < CS_NZ; k++)
        if ((cs_event_dir[k] == -1 && s->g[k] < 0.0) || (cs_event_dir[k] == 1 && s->g[k] > 0.0))
            s->g[k] = -s->g[k];
}

/* The events due at the step's end, in index order; a bounded iteration (2 NZ + 1 passes,
   one reset each).  0, or the status that ends the run. */
static int rt_events(cs_rt_instance *s) {
    double g[CS_RT_ONE(CS_NZ)];
    int pass, k;
    s->last_events = 0;
    if (CS_NZ == 0) return CS_RT_OK;
    cs_events(s->t, s->y, s->u, s->p, g);
    for (pass = 0; pass < 2 * CS_NZ + 1; pass++) {
        int action;
        for (k = 0; k < CS_NZ; k++)
            if (rt_crossed(cs_event_dir[k], s->g[k], g[k])) break;
        if (k == CS_NZ) break;
        action = cs_reset(s->t, s->y, s->u, s->p, k);
        s->last_events++;
        s->events++;
        if (action == RT_STOP || action == RT_FAIL) {
            s->stopped_by = k;
            return action == RT_FAIL ? CS_RT_EVENT_FAILED : CS_RT_STOPPED;
        }
        s->g[k] = g[k];                 /* this one has fired: its new side is the reference */
        cs_events(s->t, s->y, s->u, s->p, g);
        if (g[k] != 0.0) s->g[k] = g[k];
    }
    /* the reference for the next step; one exactly on zero keeps its old sign */
    for (k = 0; k < CS_NZ; k++)
        if (g[k] != 0.0) s->g[k] = g[k];
    return CS_RT_OK;
}

int cs_rt_step(cs_rt_instance *s) {
    double y1[CS_RT_ONE(CS_NX)], err[CS_RT_ONE(CS_NX)];
    if (s->status != CS_RT_OK) return s->status;
    if (!ros2_step(s->t, s->y, s->u, NULL, s->p, CS_RT_STEP, y1, err)) {
        s->status = CS_RT_FAILED;
        return s->status;
    }
    memcpy(s->y, y1, sizeof s->y);
    s->steps++;
    s->t = (double)s->steps * CS_RT_STEP;   /* no drift of the clock by summing steps */
    s->status = rt_events(s);
    return s->status;
}

void cs_rt_outputs(cs_rt_instance *s) {
    cs_outputs(s->t, s->y, s->u, s->p, s->out);
}

size_t cs_rt_size(void) { return sizeof(cs_rt_instance); }

int cs_rt_run(cs_rt_instance *s, long n, const double *inputs, const int *idx, int n_idx,
              double *rec) {
    long i;
    int j;
    for (i = 0; i < n; i++) {
        if (CS_NU > 0) memcpy(s->u, inputs + i * CS_NU, CS_NU * sizeof(double));
        if (cs_rt_step(s) != CS_RT_OK) return s->status;
        if (n_idx > 0) {
            cs_rt_outputs(s);
            for (j = 0; j < n_idx; j++)
                rec[i * n_idx + j] = idx[j] < CS_NX ? s->y[idx[j]] : s->out[idx[j] - CS_NX];
        }
    }
    return s->status;
}
