/* The cost of one element step through the FMU against the same step through the C ABI, for
 * scripts/host-step-cost (callgrind counts the instructions of a run of N steps; the script
 * subtracts a shorter run's to remove the setup). Both hold the body at the FMU's default
 * inputs (at rest at the origin, attitude identity, no control offsets) and take one element
 * step per call: the FMU one fmi2DoStep of one element step (communication step = element
 * step, the finest a master can take), the C ABI one flapwing_wings_step.
 *
 * Usage: step_cost fmu FMU_SO GUID N     (the FMU's default model, the fly)
 *        step_cost abi MODEL N            (flapwing_wings_from_builtin(MODEL, 0): its own step)
 * Prints the last step's vertical force (so that no step is optimised away). */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "flapwing.h"

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(so, #name)

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
  (void)env, (void)instance, (void)status, (void)category;
  fprintf(stderr, "fmu: %s\n", message);
}

static int run_fmu(const char *path, const char *guid, long n) {
  void *so = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!so) {
    fprintf(stderr, "dlopen: %s\n", dlerror());
    return 1;
  }
  LOAD(fmi2Instantiate); LOAD(fmi2SetupExperiment); LOAD(fmi2EnterInitializationMode);
  LOAD(fmi2ExitInitializationMode); LOAD(fmi2DoStep); LOAD(fmi2GetReal);
  LOAD(fmi2Terminate); LOAD(fmi2FreeInstance);
  const fmi2CallbackFunctions callbacks = {logger, NULL, NULL, NULL, NULL};
  const fmi2ValueReference vr_dt = 1, vr_fz = 30;
  fmi2Component c = fmi2Instantiate("bench", fmi2CoSimulation, guid, "", &callbacks, fmi2False, fmi2False);
  if (!c) return 1;
  fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
  fmi2EnterInitializationMode(c);
  if (fmi2ExitInitializationMode(c) != fmi2OK) return 1;
  double dt_s = 0.0, fz = 0.0;
  fmi2GetReal(c, &vr_dt, 1, &dt_s);
  for (long k = 0; k < n; k++)
    if (fmi2DoStep(c, k * dt_s, dt_s, fmi2True) != fmi2OK) return 1;
  fmi2GetReal(c, &vr_fz, 1, &fz);
  printf("fz %.17g\n", fz);
  fmi2Terminate(c);
  fmi2FreeInstance(c);
  return 0;
}

static int run_abi(const char *model, long n) {
  FlapwingWings *wings = NULL;
  if (flapwing_wings_from_builtin(model, 0.0, &wings) != FLAPWING_OK) {
    fprintf(stderr, "create: %s\n", flapwing_last_error());
    return 1;
  }
  FlapwingBodyState body;
  memset(&body, 0, sizeof body);
  body.world_from_body_wxyz[0] = 1.0;
  FlapwingWrench w;
  memset(&w, 0, sizeof w);
  for (long k = 0; k < n; k++)
    if (flapwing_wings_step(wings, &body, &w) != FLAPWING_OK) {
      fprintf(stderr, "step: %s\n", flapwing_last_error());
      return 1;
    }
  printf("fz %.17g\n", w.force_body_n[2]);
  flapwing_wings_free(wings);
  return 0;
}

int main(int argc, char **argv) {
  if (argc == 5 && strcmp(argv[1], "fmu") == 0) return run_fmu(argv[2], argv[3], strtol(argv[4], NULL, 10));
  if (argc == 4 && strcmp(argv[1], "abi") == 0) return run_abi(argv[2], strtol(argv[3], NULL, 10));
  fprintf(stderr, "usage: step_cost fmu FMU_SO GUID N | step_cost abi MODEL N\n");
  return 2;
}
