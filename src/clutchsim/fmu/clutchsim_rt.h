/* clutchsim real-time kernel (clutchsim/fmu/clutchsim_rt.h): a fixed-step simulation of one
   driveline for hardware-in-the-loop rigs, written by `clutchsim rt`.

   Usage (C99; no allocation, no I/O, no recursion in cs_rt_step):

       #include "clutchsim_rt.h"
       static cs_rt_instance s;           // one instance per simulated driveline
       cs_rt_init(&s);                    // start values of the scenario, t = 0
       for (;;) {                         // every CS_RT_STEP seconds:
           s.u[CS_RT_U_throttle] = ...;   // set the inputs (held over the step)
           if (cs_rt_step(&s) != CS_RT_OK) break;
           cs_rt_outputs(&s);             // s.out[...]: the outputs at s.t
       }

   The step: one ROS2 step (ros2.c: one Jacobian, one LU factorisation, two right-hand
   sides, two triangular solves), then the plant's event functions at the step's end; each
   one that changed sign in its direction gets the plant's reset map, in index order, at
   most 2 NZ + 1 resets per step (the same event iteration as the FMUs').  Events are
   not located within the step: a switch takes effect at the end of the step in which it
   happens, a deterministic O(h) delay.  The sizes, names and start values are in model.h,
   written for this driveline. */

#ifndef CLUTCHSIM_RT_H
#define CLUTCHSIM_RT_H

#include <stddef.h>

#include "model.h"

#define CS_RT_ONE(n) ((n) > 0 ? (n) : 1)

/* cs_rt_step's status: running; an event of the plant ended the run (CS_RT_STOPPED: as
   planned; CS_RT_EVENT_FAILED: a failure the plant declares, an engine stall); the step
   failed (a singular matrix or a value that is not finite) */
enum { CS_RT_OK = 0, CS_RT_STOPPED = 1, CS_RT_FAILED = 2, CS_RT_EVENT_FAILED = 3 };

typedef struct {
    double t;                               /* time [s] */
    double y[CS_RT_ONE(CS_NX)];             /* states (cs_state_names) */
    double u[CS_RT_ONE(CS_NU)];             /* inputs (cs_input_names): set before each step */
    double p[CS_RT_ONE(CS_NP)];             /* parameters (the plant's parameter vector) */
    double out[CS_RT_ONE(CS_NY)];           /* outputs (cs_output_names), by cs_rt_outputs */
    double g[CS_RT_ONE(CS_NZ)];             /* event functions at t (their signs before the next step) */
    unsigned long steps;                    /* steps taken */
    unsigned long events;                   /* resets applied, all steps */
    int last_events;                        /* resets applied in the last step */
    int status;                             /* CS_RT_OK, or why the run ended */
    int stopped_by;                         /* the event that stopped the run (-1: none) */
} cs_rt_instance;

/* start values of the scenario at t = 0 (the inputs at their t = 0 values) */
void cs_rt_init(cs_rt_instance *s);
/* one step of CS_RT_STEP seconds with the inputs s->u held; the status */
int cs_rt_step(cs_rt_instance *s);
/* the outputs at s->t into s->out */
void cs_rt_outputs(cs_rt_instance *s);
/* sizeof(cs_rt_instance), for drivers that allocate it themselves */
size_t cs_rt_size(void);
/* n steps with the inputs inputs[k * NU ...] held over step k; after each, the signals idx[j]
   (a state for idx < NX, else the output idx - NX) into rec[k * n_idx + j]
   (a test and benchmark driver: the step function is cs_rt_step); the status */
int cs_rt_run(cs_rt_instance *s, long n, const double *inputs, const int *idx, int n_idx,
              double *rec);

#endif
