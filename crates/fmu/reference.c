/* The C ABI's own numbers for the FMU's tests (tests/python/test_fmu.py): the wing set
 * stepped exactly as flapwing_fmu.c steps it, with no FMI in between.
 *
 * Usage: reference MODEL DT_S STEPS_PER_COMM N_COMM [QW QX QY QZ]
 *   Creates the wing set (flapwing_wings_from_builtin(MODEL, DT_S)) and, holding the body at
 *   rest at the origin with attitude Q (default: the model's initial attitude), takes N_COMM
 *   communication steps of STEPS_PER_COMM element steps each. Prints
 *     dt_s <a>          the element step
 *     attitude <a> x4   the attitude used (w x y z)
 *     weight_n <a>      mass times gravity
 *   then one line per communication step: the mean force (3) and moment (3), body frame, in
 *   the order and arithmetic of fmi2DoStep. Numbers are C99 hex floats (%a): exact.
 * Exit status 1 with the C ABI's message on stderr on any error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "flapwing.h"

static void check(FlapwingStatus s, const char *what) {
  if (s != FLAPWING_OK) {
    fprintf(stderr, "reference: %s: status %d: %s\n", what, (int)s, flapwing_last_error());
    exit(1);
  }
}

int main(int argc, char **argv) {
  if (argc != 5 && argc != 9) {
    fprintf(stderr, "usage: reference MODEL DT_S STEPS_PER_COMM N_COMM [QW QX QY QZ]\n");
    return 2;
  }
  FlapwingWings *wings = NULL;
  check(flapwing_wings_from_builtin(argv[1], strtod(argv[2], NULL), &wings), "create");
  long per = strtol(argv[3], NULL, 10), n_comm = strtol(argv[4], NULL, 10);
  FlapwingBodyProperties props;
  check(flapwing_wings_body_properties(wings, &props), "body properties");
  double dt_s;
  check(flapwing_wings_dt_s(wings, &dt_s), "dt");
  FlapwingBodyState body;
  memset(&body, 0, sizeof body);
  for (int i = 0; i < 4; i++)
    body.world_from_body_wxyz[i] = argc == 9 ? strtod(argv[5 + i], NULL) : props.initial_world_from_body_wxyz[i];
  printf("dt_s %a\n", dt_s);
  printf("attitude %a %a %a %a\n", body.world_from_body_wxyz[0], body.world_from_body_wxyz[1],
         body.world_from_body_wxyz[2], body.world_from_body_wxyz[3]);
  printf("weight_n %a\n", props.mass_kg * props.gravity_m_s2);
  for (long c = 0; c < n_comm; c++) {
    FlapwingWrench sum, w;
    for (long k = 0; k < per; k++) {
      check(flapwing_wings_step(wings, &body, &w), "step");
      for (int i = 0; i < 3; i++) {
        sum.force_body_n[i] = k == 0 ? w.force_body_n[i] : sum.force_body_n[i] + w.force_body_n[i];
        sum.moment_body_nm[i] = k == 0 ? w.moment_body_nm[i] : sum.moment_body_nm[i] + w.moment_body_nm[i];
      }
    }
    for (int i = 0; i < 3; i++) printf("%a ", sum.force_body_n[i] / (double)per);
    for (int i = 0; i < 3; i++) printf(i < 2 ? "%a " : "%a\n", sum.moment_body_nm[i] / (double)per);
  }
  flapwing_wings_free(wings);
  return 0;
}
