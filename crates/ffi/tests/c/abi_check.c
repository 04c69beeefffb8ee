/* The C ABI from C: runs one scenario and prints every number it reads, %.17g (exact on
 * parsing), for tests/c_abi.rs to compare bit for bit with the Rust WingSet.
 *
 *   abi_check fly_rest N     drosophila, the model's own step, N steps tethered at rest
 *   abi_check fly_moving N   drosophila, a host step of 20 us, wind and controls, a moving,
 *                            rotated body
 *   abi_check robobee N      the actuated robobee, its own step, N steps at rest, drive controls
 *   abi_check errors         bad input: code and message of each
 *
 * Output lines: "<what> <k> <values...>" (k the step), "error <case> <code> <message>". */
#include <flapwing.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int check(FlapwingStatus s, const char *what) {
  if (s != FLAPWING_OK) {
    fprintf(stderr, "%s failed: status %d: %s\n", what, (int)s, flapwing_last_error());
    exit(1);
  }
  return 0;
}

static void print_values(const char *what, long k, const double *v, size_t n) {
  printf("%s %ld", what, k);
  for (size_t i = 0; i < n; i++) printf(" %.17g", v[i]);
  printf("\n");
}

static void print_wrench(const char *what, long k, const FlapwingWrench *w) {
  double v[6];
  memcpy(v, w->force_body_n, sizeof w->force_body_n);
  memcpy(v + 3, w->moment_body_nm, sizeof w->moment_body_nm);
  print_values(what, k, v, 6);
}

static void print_header(const FlapwingWings *wings) {
  size_t n = 0;
  double dt = 0.0;
  FlapwingBodyProperties b;
  check(flapwing_wings_count(wings, &n), "count");
  check(flapwing_wings_dt_s(wings, &dt), "dt_s");
  check(flapwing_wings_body_properties(wings, &b), "body_properties");
  double count = (double)n;
  print_values("count", 0, &count, 1);
  print_values("dt", 0, &dt, 1);
  double props[18];
  props[0] = b.mass_kg;
  memcpy(props + 1, b.inertia_body_kg_m2, 9 * sizeof(double));
  props[10] = b.gravity_m_s2;
  memcpy(props + 11, b.initial_position_m, 3 * sizeof(double));
  memcpy(props + 14, b.initial_world_from_body_wxyz, 4 * sizeof(double));
  print_values("body", 0, props, 18);
}

/* Everything one step reports. */
static void print_step(const FlapwingWings *wings, long k, const FlapwingWrench *total) {
  print_wrench("total", k, total);
  for (uint32_t t = 0; t < 4; t++) {
    FlapwingWrench w;
    char name[32];
    check(flapwing_wings_term(wings, t, &w), "term");
    snprintf(name, sizeof name, "term%u", (unsigned)t);
    print_wrench(name, k, &w);
  }
  FlapwingWrench inertia;
  check(flapwing_wings_inertia(wings, &inertia), "inertia");
  print_wrench("inertia", k, &inertia);
  size_t n = 0;
  check(flapwing_wings_count(wings, &n), "count");
  for (size_t i = 0; i < n; i++) {
    FlapwingWingState s;
    char name[32];
    check(flapwing_wings_wing(wings, i, &s), "wing");
    double v[10] = {s.stroke_rad,        s.pitch_rad,        s.deviation_rad,
                    s.stroke_rate_rad_s, s.pitch_rate_rad_s, s.deviation_rate_rad_s,
                    s.force_body_n[0],   s.force_body_n[1],  s.force_body_n[2],
                    s.hinge_moment_nm};
    snprintf(name, sizeof name, "wing%zu", i);
    print_values(name, k, v, 10);
  }
}

static void print_time(const FlapwingWings *wings, long k) {
  double t = 0.0;
  check(flapwing_wings_time_s(wings, &t), "time_s");
  print_values("time", k, &t, 1);
}

static FlapwingBodyState at_rest(void) {
  FlapwingBodyState s;
  memset(&s, 0, sizeof s);
  s.world_from_body_wxyz[0] = 1.0;
  return s;
}

/* The moving, rotated body of step k (tests/c_abi.rs has the same formula). */
static FlapwingBodyState moving(long k) {
  double x = (double)k;
  FlapwingBodyState s;
  s.position_m[0] = 0.001 * x;
  s.position_m[1] = -0.002 * x;
  s.position_m[2] = 0.1 + 0.0005 * x;
  s.world_from_body_wxyz[0] = 0.953150604096219;
  s.world_from_body_wxyz[1] = 0.10033164253644411;
  s.world_from_body_wxyz[2] = 0.28092859910204354;
  s.world_from_body_wxyz[3] = -0.050165821268222055;
  s.velocity_world_m_s[0] = 0.3 - 0.01 * x;
  s.velocity_world_m_s[1] = 0.05;
  s.velocity_world_m_s[2] = -0.1 + 0.02 * x;
  s.angular_velocity_body_rad_s[0] = 1.5;
  s.angular_velocity_body_rad_s[1] = -2.0 + 0.1 * x;
  s.angular_velocity_body_rad_s[2] = 0.5;
  return s;
}

static void run(FlapwingWings *wings, long n, int move) {
  print_header(wings);
  for (long k = 0; k < n; k++) {
    FlapwingBodyState s = move ? moving(k) : at_rest();
    FlapwingWrench total;
    check(flapwing_wings_step(wings, &s, &total), "step");
    print_step(wings, k, &total);
  }
  print_time(wings, n);
}

static void error_line(const char *what, FlapwingStatus s) {
  printf("error %s %d %s\n", what, (int)s, flapwing_last_error());
}

static void errors(void) {
  FlapwingWings *wings = (FlapwingWings *)&wings; /* not NULL: must be overwritten */
  FlapwingStatus s = flapwing_wings_from_builtin("no_such_fly", 0.0, &wings);
  error_line("unknown_builtin", s);
  if (wings != NULL) {
    printf("error unknown_builtin_out_not_null 0 -\n");
  }
  error_line("missing_file",
             flapwing_wings_from_file("/nonexistent/flapwing/fly.toml", 0.0, &wings));
  error_line("null_name", flapwing_wings_from_builtin(NULL, 0.0, &wings));
  error_line("null_out", flapwing_wings_from_builtin("drosophila", 0.0, NULL));
  error_line("negative_dt", flapwing_wings_from_builtin("drosophila", -1e-5, &wings));
  error_line("nan_dt", flapwing_wings_from_builtin("drosophila", NAN, &wings));

  FlapwingWrench w;
  size_t n;
  error_line("null_handle_step", flapwing_wings_step(NULL, NULL, &w));
  error_line("null_handle_count", flapwing_wings_count(NULL, &n));
  flapwing_wings_free(NULL); /* a no-op */

  check(flapwing_wings_from_builtin("drosophila", 0.0, &wings), "from_builtin");
  FlapwingBodyState b = at_rest();
  b.velocity_world_m_s[1] = NAN;
  error_line("nan_state", flapwing_wings_step(wings, &b, &w));
  error_line("null_state", flapwing_wings_step(wings, NULL, &w));
  error_line("null_total", flapwing_wings_step(wings, &b, NULL));
  FlapwingWingState ws;
  error_line("wing_out_of_range", flapwing_wings_wing(wings, 2, &ws));
  error_line("term_out_of_range", flapwing_wings_term(wings, 4, &w));
  b = at_rest();
  check(flapwing_wings_step(wings, &b, &w), "step after errors");
  error_line("ok_after_errors", FLAPWING_OK);
  flapwing_wings_free(wings);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: abi_check fly_rest|fly_moving|robobee N | errors\n");
    return 2;
  }
  printf("version 0 %s\n", flapwing_version());
  const char *scenario = argv[1];
  long n = argc > 2 ? strtol(argv[2], NULL, 10) : 0;
  FlapwingWings *wings = NULL;
  if (strcmp(scenario, "fly_rest") == 0) {
    check(flapwing_wings_from_builtin("drosophila", 0.0, &wings), "from_builtin");
    run(wings, n, 0);
  } else if (strcmp(scenario, "fly_moving") == 0) {
    check(flapwing_wings_from_builtin("drosophila", 2.0e-5, &wings), "from_builtin");
    FlapwingControls c;
    memset(&c, 0, sizeof c);
    c.amplitude_rad = 0.05;
    c.diff_pitch_bias_rad = 0.02;
    check(flapwing_wings_set_controls(wings, &c), "set_controls");
    const double wind[3] = {0.1, -0.2, 0.05};
    check(flapwing_wings_set_wind(wings, wind), "set_wind");
    run(wings, n, 1);
  } else if (strcmp(scenario, "robobee") == 0) {
    check(flapwing_wings_from_builtin("robobee", 0.0, &wings), "from_builtin");
    FlapwingControls c;
    memset(&c, 0, sizeof c);
    c.amplitude_v = 5.0;
    c.diff_bias_v = 2.0;
    check(flapwing_wings_set_controls(wings, &c), "set_controls");
    run(wings, n, 0);
  } else if (strcmp(scenario, "errors") == 0) {
    errors();
  } else {
    fprintf(stderr, "unknown scenario %s\n", scenario);
    return 2;
  }
  flapwing_wings_free(wings);
  return 0;
}
