// The C ABI from C++: the scenarios of abi_check.c (fly_rest, fly_moving, robobee) through a
// small RAII wrapper, printing the same lines ("<what> <k> <values...>", %.17g) for
// tests/c_abi.rs to compare bit for bit with the Rust WingSet.
#include <flapwing.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Error : std::runtime_error {
  FlapwingStatus status;
  Error(FlapwingStatus s, const std::string &what)
      : std::runtime_error(std::string(flapwing_last_error()) + " (via " + what + ")"), status(s) {}
};

void ok(FlapwingStatus s, const char *what) {
  if (s != FLAPWING_OK) throw Error(s, what);
}

struct Free {
  void operator()(FlapwingWings *w) const { flapwing_wings_free(w); }
};

class Wings {
 public:
  static Wings builtin(const std::string &name, double dt_s) {
    FlapwingWings *w = nullptr;
    ok(flapwing_wings_from_builtin(name.c_str(), dt_s, &w), "flapwing_wings_from_builtin");
    return Wings(w);
  }
  std::size_t count() const {
    std::size_t n = 0;
    ok(flapwing_wings_count(h_.get(), &n), "count");
    return n;
  }
  double dt_s() const {
    double dt = 0;
    ok(flapwing_wings_dt_s(h_.get(), &dt), "dt_s");
    return dt;
  }
  double time_s() const {
    double t = 0;
    ok(flapwing_wings_time_s(h_.get(), &t), "time_s");
    return t;
  }
  FlapwingBodyProperties body() const {
    FlapwingBodyProperties b{};
    ok(flapwing_wings_body_properties(h_.get(), &b), "body_properties");
    return b;
  }
  FlapwingWrench step(const FlapwingBodyState &s) {
    FlapwingWrench w{};
    ok(flapwing_wings_step(h_.get(), &s, &w), "step");
    return w;
  }
  FlapwingWrench term(std::uint32_t t) const {
    FlapwingWrench w{};
    ok(flapwing_wings_term(h_.get(), t, &w), "term");
    return w;
  }
  FlapwingWrench inertia() const {
    FlapwingWrench w{};
    ok(flapwing_wings_inertia(h_.get(), &w), "inertia");
    return w;
  }
  FlapwingWingState wing(std::size_t i) const {
    FlapwingWingState s{};
    ok(flapwing_wings_wing(h_.get(), i, &s), "wing");
    return s;
  }
  void controls(const FlapwingControls &c) { ok(flapwing_wings_set_controls(h_.get(), &c), "controls"); }
  void wind(const std::array<double, 3> &w) { ok(flapwing_wings_set_wind(h_.get(), w.data()), "wind"); }

 private:
  explicit Wings(FlapwingWings *w) : h_(w) {}
  std::unique_ptr<FlapwingWings, Free> h_;
};

void line(const std::string &what, long k, const std::vector<double> &v) {
  std::printf("%s %ld", what.c_str(), k);
  for (double x : v) std::printf(" %.17g", x);
  std::printf("\n");
}

void wrench_line(const std::string &what, long k, const FlapwingWrench &w) {
  line(what, k,
       {w.force_body_n[0], w.force_body_n[1], w.force_body_n[2], w.moment_body_nm[0],
        w.moment_body_nm[1], w.moment_body_nm[2]});
}

FlapwingBodyState at_rest() {
  FlapwingBodyState s{};
  s.world_from_body_wxyz[0] = 1.0;
  return s;
}

// The moving, rotated body of step k (as in abi_check.c and tests/c_abi.rs).
FlapwingBodyState moving(long k) {
  const double x = static_cast<double>(k);
  FlapwingBodyState s{};
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

void run(Wings &wings, long n, bool move) {
  line("count", 0, {static_cast<double>(wings.count())});
  line("dt", 0, {wings.dt_s()});
  const FlapwingBodyProperties b = wings.body();
  std::vector<double> props{b.mass_kg};
  props.insert(props.end(), b.inertia_body_kg_m2, b.inertia_body_kg_m2 + 9);
  props.push_back(b.gravity_m_s2);
  props.insert(props.end(), b.initial_position_m, b.initial_position_m + 3);
  props.insert(props.end(), b.initial_world_from_body_wxyz, b.initial_world_from_body_wxyz + 4);
  line("body", 0, props);
  for (long k = 0; k < n; ++k) {
    wrench_line("total", k, wings.step(move ? moving(k) : at_rest()));
    for (std::uint32_t t = 0; t < 4; ++t) wrench_line("term" + std::to_string(t), k, wings.term(t));
    wrench_line("inertia", k, wings.inertia());
    for (std::size_t i = 0; i < wings.count(); ++i) {
      const FlapwingWingState s = wings.wing(i);
      line("wing" + std::to_string(i), k,
           {s.stroke_rad, s.pitch_rad, s.deviation_rad, s.stroke_rate_rad_s, s.pitch_rate_rad_s,
            s.deviation_rate_rad_s, s.force_body_n[0], s.force_body_n[1], s.force_body_n[2],
            s.hinge_moment_nm});
    }
  }
  line("time", n, {wings.time_s()});
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: abi_check_cpp fly_rest|fly_moving|robobee N\n");
    return 2;
  }
  const std::string scenario = argv[1];
  const long n = std::strtol(argv[2], nullptr, 10);
  try {
    if (scenario == "fly_rest") {
      Wings w = Wings::builtin("drosophila", 0.0);
      run(w, n, false);
    } else if (scenario == "fly_moving") {
      Wings w = Wings::builtin("drosophila", 2.0e-5);
      FlapwingControls c{};
      c.amplitude_rad = 0.05;
      c.diff_pitch_bias_rad = 0.02;
      w.controls(c);
      w.wind({0.1, -0.2, 0.05});
      run(w, n, true);
    } else if (scenario == "robobee") {
      Wings w = Wings::builtin("robobee", 0.0);
      FlapwingControls c{};
      c.amplitude_v = 5.0;
      c.diff_bias_v = 2.0;
      w.controls(c);
      run(w, n, false);
    } else {
      std::fprintf(stderr, "unknown scenario %s\n", scenario.c_str());
      return 2;
    }
    // An error through the wrapper: a C++ exception carrying the code and message.
    try {
      Wings::builtin("no_such_fly", 0.0);
      std::printf("error unknown_builtin 0 accepted\n");
    } catch (const Error &e) {
      std::printf("error unknown_builtin %d %s\n", static_cast<int>(e.status), e.what());
    }
  } catch (const std::exception &e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
