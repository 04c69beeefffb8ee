/* The fruit fly's wings on a tethered body from C: one wingbeat at the model's own step,
 * the wingbeat-mean force and moment on the body against its weight.
 *
 * Build (from the workspace root, after `cargo build --release -p flapwing-ffi`):
 *   cc -std=c11 -O2 -I crates/ffi/include crates/ffi/examples/c/hover_loads.c \
 *      target/release/libflapwing.a -lm -lpthread -ldl -o hover_loads
 *   ./hover_loads            (or ./hover_loads path/to/model.toml) */
#include <flapwing.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv) {
  FlapwingWings *wings = NULL;
  FlapwingStatus s = argc > 1 ? flapwing_wings_from_file(argv[1], 0.0, &wings)
                              : flapwing_wings_from_builtin("drosophila", 0.0, &wings);
  if (s != FLAPWING_OK) {
    fprintf(stderr, "flapwing %s: error %d: %s\n", flapwing_version(), (int)s,
            flapwing_last_error());
    return 1;
  }
  double dt_s = 0.0, freq_hz = 0.0;
  FlapwingBodyProperties body;
  flapwing_wings_dt_s(wings, &dt_s);
  flapwing_wings_freq_hz(wings, &freq_hz);
  flapwing_wings_body_properties(wings, &body);

  /* Tethered: the body stays at its initial pose, at rest. */
  FlapwingBodyState state;
  memset(&state, 0, sizeof state);
  for (int i = 0; i < 3; i++) state.position_m[i] = body.initial_position_m[i];
  for (int i = 0; i < 4; i++) state.world_from_body_wxyz[i] = body.initial_world_from_body_wxyz[i];

  /* One wingbeat: the model's own step divides it into a whole number of steps. */
  const long steps = lround(1.0 / (freq_hz * dt_s));
  double mean[6] = {0};
  for (long k = 0; k < steps; k++) {
    FlapwingWrench w;
    s = flapwing_wings_step(wings, &state, &w);
    if (s != FLAPWING_OK) {
      fprintf(stderr, "step: error %d: %s\n", (int)s, flapwing_last_error());
      flapwing_wings_free(wings);
      return 1;
    }
    for (int i = 0; i < 3; i++) {
      mean[i] += w.force_body_n[i];
      mean[3 + i] += w.moment_body_nm[i];
    }
  }
  for (int i = 0; i < 6; i++) mean[i] /= (double)steps;

  double weight_n = body.mass_kg * body.gravity_m_s2;
  printf("flapwing %s: one wingbeat at %.4g Hz, %ld steps of %.4g s\n", flapwing_version(), freq_hz,
         steps, dt_s);
  printf("mean force, body frame:  [%.4g, %.4g, %.4g] N (weight %.4g N)\n", mean[0], mean[1],
         mean[2], weight_n);
  printf("mean moment, body frame: [%.4g, %.4g, %.4g] N m\n", mean[3], mean[4], mean[5]);
  flapwing_wings_free(wings);
  return 0;
}
