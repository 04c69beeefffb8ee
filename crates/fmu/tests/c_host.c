/* A minimal C master of the FMU, for tests/python/test_fmu.py (run under valgrind when the
 * machine has it): loads binaries/linux64/flapwing_wings.so with dlopen and runs three
 * instances one after another: a good run, a bad model name and a NaN input, each freed.
 * Prints each FMI status and the last force_body_n_z; the logger prints the FMU's messages.
 * The good run also takes an FMU state halfway, sets it back at the end and steps the second
 * half again (the last force again), calls the state functions with NULL, and frees the state.
 * Usage: c_host FMU_SO GUID */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
  (void)env, (void)instance;
  va_list ap;
  va_start(ap, message);
  printf("log %d %s: ", (int)status, category);
  vprintf(message, ap);
  printf("\n");
  va_end(ap);
}

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(so, #name)

int main(int argc, char **argv) {
  if (argc != 3) return 2;
  void *so = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!so) {
    printf("dlopen: %s\n", dlerror());
    return 1;
  }
  LOAD(fmi2Instantiate); LOAD(fmi2SetupExperiment); LOAD(fmi2EnterInitializationMode);
  LOAD(fmi2ExitInitializationMode); LOAD(fmi2DoStep); LOAD(fmi2GetReal); LOAD(fmi2SetReal);
  LOAD(fmi2SetString); LOAD(fmi2Terminate); LOAD(fmi2FreeInstance);
  LOAD(fmi2GetFMUstate); LOAD(fmi2SetFMUstate); LOAD(fmi2FreeFMUstate);
  const fmi2CallbackFunctions callbacks = {logger, NULL, NULL, NULL, NULL};
  const fmi2ValueReference vr_model = 0, vr_dt = 1, vr_vz = 11, vr_fz = 30;
  for (int run = 0; run < 3; run++) {
    fmi2Component c = fmi2Instantiate("host", fmi2CoSimulation, argv[2], "", &callbacks, fmi2False, fmi2False);
    if (!c) return 1;
    fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    if (run == 1) {
      fmi2String bad = "no_such_fly";
      fmi2SetString(c, &vr_model, 1, &bad);
    }
    fmi2EnterInitializationMode(c);
    printf("run %d init %d\n", run, (int)fmi2ExitInitializationMode(c));
    double dt_s = 0.0, fz = 0.0;
    fmi2GetReal(c, &vr_dt, 1, &dt_s);
    if (run == 2) {
      const double nan = NAN;
      fmi2SetReal(c, &vr_vz, 1, &nan);
    }
    fmi2Status s = fmi2OK;
    fmi2FMUstate state = NULL;
    int k = 0; /* 50 communication steps of two element steps */
    for (; k < 50 && s == fmi2OK; k++) {
      if (run == 0 && k == 25) printf("run 0 get %d\n", (int)fmi2GetFMUstate(c, &state));
      s = fmi2DoStep(c, 2.0 * k * dt_s, 2.0 * dt_s, fmi2True);
    }
    fmi2GetReal(c, &vr_fz, 1, &fz);
    printf("run %d steps %d status %d fz %.17g\n", run, s == fmi2OK ? k : k - 1, (int)s, fz);
    if (run == 0) {
      printf("run 0 set %d\n", (int)fmi2SetFMUstate(c, state));
      for (k = 25; k < 50 && s == fmi2OK; k++) s = fmi2DoStep(c, 2.0 * k * dt_s, 2.0 * dt_s, fmi2True);
      fmi2GetReal(c, &vr_fz, 1, &fz);
      printf("run 0 again status %d fz %.17g\n", (int)s, fz);
      printf("run 0 null get %d set %d\n", (int)fmi2GetFMUstate(c, NULL), (int)fmi2SetFMUstate(c, NULL));
      const fmi2Status freed = fmi2FreeFMUstate(c, &state);
      printf("run 0 free %d %s\n", (int)freed, state ? "kept" : "null");
    }
    fmi2Terminate(c);
    fmi2FreeInstance(c);
  }
  dlclose(so);
  return 0;
}
