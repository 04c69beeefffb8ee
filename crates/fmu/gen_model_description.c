/* Writes the FMU's modelDescription.xml (FMI 2.0 co-simulation) to stdout from the variable
 * table in flapwing_fmu_vars.h. build.sh compiles and runs it; nothing else uses it.
 * Usage: gen_model_description VERSION */
#include <math.h>
#include <stdio.h>

#include "flapwing_fmu_vars.h"

typedef struct {
  const char *name, *causality, *variability, *unit, *description;
  int vr;
  double start;
} Real;

static const Real reals[] = {
#define ROW(name, vr, causality, variability, start, unit, description) \
  {#name, causality, variability, unit, description, vr, start},
    FLAPWING_FMU_REALS(ROW)
#undef ROW
};
#define N_REALS ((int)(sizeof reals / sizeof reals[0]))

/* Index (1-based, in ModelVariables order) of each variable: the String first, then the
 * Reals in table order, then the Integer. */
#define INDEX_MODEL 1
#define INDEX_REAL(i) (2 + (i))
#define INDEX_STEPS (2 + N_REALS)
#define INDEX_TRIM (3 + N_REALS)

int main(int argc, char **argv) {
  const char *version = argc > 1 ? argv[1] : "0.1.0";
  char guid[40];
  flapwing_fmu_guid(guid);
  printf("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  printf("<fmiModelDescription fmiVersion=\"2.0\" modelName=\"flapwing_wings\" guid=\"%s\"\n", guid);
  printf("  description=\"flapwing's flapping wings as a force element: body state and controls in, "
         "wing wrench about the centre of mass (body frame) out\"\n");
  printf("  version=\"%s\" generationTool=\"flapwing crates/fmu (gen_model_description.c)\"\n", version);
  printf("  variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">\n");
  printf("  <CoSimulation modelIdentifier=\"%s\" canHandleVariableCommunicationStepSize=\"true\"\n",
         FLAPWING_FMU_MODEL_IDENTIFIER);
  printf("    canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"true\"\n");
  printf("    canSerializeFMUstate=\"false\" providesDirectionalDerivative=\"false\"/>\n");
  printf("  <UnitDefinitions>\n");
#define UNIT(name, kg, m, s, A, rad)                                                   \
  printf("    <Unit name=\"%s\"><BaseUnit%s%s%s%s%s/></Unit>\n", name,                    \
         kg ? " kg=\"" #kg "\"" : "", m ? " m=\"" #m "\"" : "", s ? " s=\"" #s "\"" : "", \
         A ? " A=\"" #A "\"" : "", rad ? " rad=\"" #rad "\"" : "");
  FLAPWING_FMU_UNITS(UNIT)
#undef UNIT
  printf("  </UnitDefinitions>\n");
  printf("  <LogCategories>\n");
  printf("    <Category name=\"logStatusError\" description=\"Errors and discarded steps\"/>\n");
  printf("    <Category name=\"logStatusWarning\" description=\"Warnings\"/>\n");
  printf("    <Category name=\"logCalls\" description=\"Each FMI call (debug logging)\"/>\n");
  printf("  </LogCategories>\n");
  /* The default model's element step (the fruit fly: 1 / (218 Hz x 100)) and 218 of them
   * (2.18 wingbeats); tests/python/test_fmu.py checks the step against the C ABI's. */
  printf("  <DefaultExperiment startTime=\"0\" stopTime=\"0.05\" stepSize=\"%.17g\"/>\n", 1.0 / (218.0 * 20.0));
  printf("  <ModelVariables>\n");
  printf("    <!-- index %d -->\n", INDEX_MODEL);
  printf("    <ScalarVariable name=\"model\" valueReference=\"0\" causality=\"parameter\" "
         "variability=\"fixed\" initial=\"exact\"\n      description=\"%s\">\n",
         FLAPWING_FMU_MODEL_DESCRIPTION);
  printf("      <String start=\"%s\"/>\n    </ScalarVariable>\n", FLAPWING_FMU_DEFAULT_MODEL);
  for (int i = 0; i < N_REALS; i++) {
    const Real *r = &reals[i];
    printf("    <!-- index %d -->\n", INDEX_REAL(i));
    printf("    <ScalarVariable name=\"%s\" valueReference=\"%d\" causality=\"%s\" variability=\"%s\"",
           r->name, r->vr, r->causality, r->variability);
    /* Parameters are exact; calculated parameters and outputs are calculated (the default
     * for both, but stated); inputs take no initial attribute in FMI 2.0. */
    if (!isnan(r->start)) {
      if (r->causality[0] == 'p') printf(" initial=\"exact\"");
    } else {
      printf(" initial=\"calculated\"");
    }
    printf("\n      description=\"%s\">\n      <Real", r->description);
    if (r->unit[0]) printf(" unit=\"%s\"", r->unit);
    if (!isnan(r->start)) printf(" start=\"%.17g\"", r->start);
    printf("/>\n    </ScalarVariable>\n");
  }
  printf("    <!-- index %d -->\n", INDEX_STEPS);
  printf("    <ScalarVariable name=\"element_steps\" valueReference=\"0\" causality=\"output\" "
         "variability=\"discrete\" initial=\"calculated\"\n      description=\"%s\">\n",
         FLAPWING_FMU_STEPS_DESCRIPTION);
  printf("      <Integer/>\n    </ScalarVariable>\n");
  printf("    <!-- index %d -->\n", INDEX_TRIM);
  printf("    <ScalarVariable name=\"trim\" valueReference=\"0\" causality=\"parameter\" "
         "variability=\"fixed\" initial=\"exact\"\n      description=\"%s\">\n",
         FLAPWING_FMU_TRIM_DESCRIPTION);
  printf("      <Boolean start=\"false\"/>\n    </ScalarVariable>\n");
  printf("  </ModelVariables>\n");

  /* Outputs: computed by doStep from the inputs at the step's start, so no direct
   * feedthrough (setting an input does not change an output until the next doStep). */
  printf("  <ModelStructure>\n    <Outputs>\n");
  for (int i = 0; i < N_REALS; i++)
    if (reals[i].causality[0] == 'o')
      printf("      <Unknown index=\"%d\" dependencies=\"\"/>\n", INDEX_REAL(i));
  printf("      <Unknown index=\"%d\" dependencies=\"\"/>\n", INDEX_STEPS);
  printf("    </Outputs>\n    <InitialUnknowns>\n");
  /* The element step depends on the model and the dt_s parameter; outputs start at zero. */
  for (int i = 0; i < N_REALS; i++) {
    if (reals[i].vr == VR_element_dt_s)
      printf("      <Unknown index=\"%d\" dependencies=\"%d %d\"/>\n", INDEX_REAL(i), INDEX_MODEL,
             INDEX_REAL(VR_dt_s));
    /* The trim's results depend on the model, the step and the trim's parameters. */
    else if (reals[i].causality[0] == 'c')
      printf("      <Unknown index=\"%d\" dependencies=\"%d %d %d %d %d\"/>\n", INDEX_REAL(i),
             INDEX_MODEL, INDEX_REAL(VR_dt_s), INDEX_REAL(VR_trim_forward_speed_m_s),
             INDEX_REAL(VR_trim_climb_rate_m_s), INDEX_TRIM);
    else if (reals[i].causality[0] == 'o')
      printf("      <Unknown index=\"%d\" dependencies=\"\"/>\n", INDEX_REAL(i));
  }
  printf("      <Unknown index=\"%d\" dependencies=\"\"/>\n", INDEX_STEPS);
  printf("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n");
  return 0;
}
