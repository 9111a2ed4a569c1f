/* The FMI functions whose FMI 2.0 and FMI 3.0 forms differ only in their names and types
   (clutchsim/fmu/fmi_common.c), written once over the core (plant_core.c) for both.  The
   glue of each version (fmi2_me.c, fmi3_me.c) includes it after it defines

     FMI_FN(name)          the function's name: fmi2##name or fmi3##name
     FMI_EXPORT            the export attribute
     FMI_INSTANCE          the instance type (fmi2Component, fmi3Instance)
     FMI_STATUS, FMI_BOOLEAN, FMI_STRING, FMI_TRUE, FMI_FALSE
     FMI_GET_DERIVATIVES   the derivatives' getter (fmi2GetDerivatives,
                           fmi3GetContinuousStateDerivatives) */

#define FMI_M ((Instance *)instance)

FMI_EXPORT FMI_STATUS FMI_FN(SetDebugLogging)(FMI_INSTANCE instance, FMI_BOOLEAN on, size_t n,
                                              const FMI_STRING cats[]) {
    (void)n; (void)cats;
    FMI_M->logging = on;
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(ExitInitializationMode)(FMI_INSTANCE instance) {
    core_exit_init(FMI_M);
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(EnterEventMode)(FMI_INSTANCE instance) {
    FMI_M->mode = MODE_EVENT;
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(EnterContinuousTimeMode)(FMI_INSTANCE instance) {
    FMI_M->mode = MODE_CONT;
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(Terminate)(FMI_INSTANCE instance) {
    FMI_M->mode = MODE_TERMINATED;
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(Reset)(FMI_INSTANCE instance) {
    core_start(FMI_M);
    return (FMI_STATUS)ST_OK;
}

/* no time events and nothing to do after a step (completedIntegratorStepNotNeeded) */
FMI_EXPORT FMI_STATUS FMI_FN(CompletedIntegratorStep)(FMI_INSTANCE instance, FMI_BOOLEAN no_prior,
                                                      FMI_BOOLEAN *enter_event, FMI_BOOLEAN *terminate) {
    (void)instance; (void)no_prior;
    *enter_event = FMI_FALSE;
    *terminate = FMI_FALSE;
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(SetTime)(FMI_INSTANCE instance, double t) {
    FMI_M->t = t;
    changed(FMI_M);
    return (FMI_STATUS)ST_OK;
}

FMI_EXPORT FMI_STATUS FMI_FN(SetContinuousStates)(FMI_INSTANCE instance, const double x[], size_t n) {
    return (FMI_STATUS)core_set_states(FMI_M, x, n);
}

FMI_EXPORT FMI_STATUS FMI_GET_DERIVATIVES(FMI_INSTANCE instance, double dx[], size_t n) {
    return (FMI_STATUS)core_get_derivatives(FMI_M, dx, n);
}

FMI_EXPORT FMI_STATUS FMI_FN(GetEventIndicators)(FMI_INSTANCE instance, double g[], size_t n) {
    return (FMI_STATUS)core_get_indicators(FMI_M, g, n);
}

FMI_EXPORT FMI_STATUS FMI_FN(GetContinuousStates)(FMI_INSTANCE instance, double x[], size_t n) {
    return (FMI_STATUS)core_get_states(FMI_M, x, n);
}

FMI_EXPORT FMI_STATUS FMI_FN(GetNominalsOfContinuousStates)(FMI_INSTANCE instance, double x[], size_t n) {
    (void)instance;
    core_nominals(x, n);
    return (FMI_STATUS)ST_OK;
}
