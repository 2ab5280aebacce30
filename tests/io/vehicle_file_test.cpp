#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "config_refusal.h"
#include "core/motor_numbering.h"
#include "io/key_value.h"
#include "io/params_file.h"
#include "io/vehicle_file.h"
#include "model/dynamics.h"
#include "test_support.h"

namespace quadfdi {
namespace {

std::string library(const std::string& file) { return std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/" + file; }

// Every described vehicle: the library's three, and the held-out airframes no shipped model was
// trained on (configs/vehicles/held-out/, docs/results/held-out-vehicles/).
const char* const kDescribed[] = {"crazyflie2.toml", "racer250.toml", "quad450.toml", "held-out/x500.toml",
                                  "held-out/solo.toml"};

// A valid description (PX4 numbering, square X) that the refusal tests break one line at a time.
const char* kValid = R"(name = "test quad"
source = "unit test"
motor_numbering = "PX4 quad X"
frame = "frd"
mass = 1.5
inertia_xx = 0.03
inertia_yy = 0.03
inertia_zz = 0.05
yaw_moment_coeff = 0.06
motor_time_constant = 0.02
[thrust]
max = 7.0
min = 0.05
model_factor = 0.8
[motor.1]
x = 0.13
y = 0.21
spin = "ccw"
[motor.2]
x = -0.13
y = -0.21
spin = "ccw"
[motor.3]
x = 0.13
y = -0.21
spin = "cw"
[motor.4]
x = -0.13
y = 0.21
spin = "cw"
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("test text lacks '" + from + "'");
  return text.replace(at, from.size(), to);
}

std::string refusal(const std::string& text) {
  return test::configRefusal([&] { vehicleDescriptionFromText(text, "quad.toml"); });
}

TEST(VehicleFile, LibraryVehiclesLoadValidateAndHoverAtEquilibrium) {
  for (const char* file : kDescribed) {
    const VehicleDescription d = loadVehicleDescription(library(file));
    const VehicleParams& p = d.params;
    EXPECT_EQ(validate(p), "") << file;
    EXPECT_FALSE(d.name.empty());
    EXPECT_FALSE(d.source.empty());
    // Hover well inside the thrust range: at most 70 % of max, well above min.
    const double hover = p.hoverThrust();
    EXPECT_GT(hover, 2.0 * p.min_thrust) << file;
    EXPECT_LT(hover, 0.7 * p.max_thrust) << file;
    // The same params through the --params path.
    EXPECT_EQ(vehicleParamsToText(loadVehicleParams(library(file))), vehicleParamsToText(p)) << file;
    // State derivative zero at hover thrust to round-off.
    const RigidBodyModel m = RigidBodyModel::fromParams(p);
    State dx;
    stateDerivative(m, test::hoverState(Vec3(0.0, 0.0, 1.0)), Input::Constant(hover), dx);
    EXPECT_LT(dx.cwiseAbs().maxCoeff(), 1e-14) << file;
  }
}

TEST(VehicleFile, LibraryVehiclesHoverUnderLqrFromAnOffset) {
  for (const char* file : kDescribed) {
    const VehicleParams p = loadVehicleDescription(library(file)).params;
    auto lqr = test::makeOrDie(p, ControllerKind::kLqr);
    const Vec3 goal(0.0, 0.0, 1.0);
    lqr->setGoal(goal);
    State x0 = test::hoverState(Vec3(0.2, -0.15, 0.8));
    x0(idx::kRoll) = 0.1;
    x0(idx::kPitch) = -0.08;
    x0(idx::kYaw) = 0.2;
    SimulationSettings s;
    // LQR with the seed's weights (Q = I, R = I in N²) is slow on a heavy vehicle, whose thrusts are
    // large in newtons: the 1.5 kg quad's slowest closed-loop mode takes tens of seconds.
    s.steps = 20000;  // 40 s
    FlightLog log;
    const FlightSummary sum = ClosedLoopSimulator(p, s).run(*lqr, x0, &log);
    ASSERT_EQ(sum.end_status, StepStatus::kOk) << file;
    const State& end = sum.final_state;
    EXPECT_LT((end.segment<3>(idx::kPos) - goal).norm(), 1e-3) << file;
    EXPECT_LT(end.segment<3>(idx::kAtt).norm(), 1e-3) << file;
    EXPECT_LT(end.segment<3>(idx::kVel).norm(), 1e-3) << file;
  }
}

TEST(VehicleFile, LibraryGeometryAndMotorNumbering) {
  const VehicleDescription cf = loadVehicleDescription(library("crazyflie2.toml"));
  EXPECT_EQ(cf.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{1, 2, 3, 4}));
  EXPECT_EQ(cf.params.rollLever(), cf.params.pitchLever());
  const VehicleDescription racer = loadVehicleDescription(library("racer250.toml"));
  // Betaflight: 1 back-right, 2 front-right, 3 back-left, 4 front-left.
  EXPECT_EQ(racer.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{2, 1, 3, 4}));
  EXPECT_EQ(racer.autopilot_motor_of_quadfdi_motor, (std::array<int, 4>{2, 1, 3, 4}));
  EXPECT_EQ(racer.params.pitchLever(), 0.075);  // stretched X: |x| ≠ |y|
  EXPECT_EQ(racer.params.rollLever(), 0.10);
  const VehicleDescription iris = loadVehicleDescription(library("quad450.toml"));
  // PX4 quad X: 1 front-right, 2 back-left, 3 front-left, 4 back-right.
  EXPECT_EQ(iris.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{1, 3, 4, 2}));
  EXPECT_EQ(iris.autopilot_motor_of_quadfdi_motor, (std::array<int, 4>{1, 4, 2, 3}));
  EXPECT_NEAR(iris.params.rollLever(), 0.21, 1e-15);
  // The held-out airframes: PX4 numbering too; the x500 a square X, the Solo 1.5 % longer than wide.
  const VehicleDescription x500 = loadVehicleDescription(library("held-out/x500.toml"));
  EXPECT_EQ(x500.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{1, 3, 4, 2}));
  EXPECT_EQ(x500.params.rollLever(), x500.params.pitchLever());
  const VehicleDescription solo = loadVehicleDescription(library("held-out/solo.toml"));
  EXPECT_EQ(solo.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{1, 3, 4, 2}));
  EXPECT_EQ(solo.params.pitchLever(), 0.14745);
  EXPECT_EQ(solo.params.rollLever(), 0.14525);
}

TEST(VehicleFile, RoundTripThroughText) {
  for (const char* file : kDescribed) {
    const VehicleDescription a = loadVehicleDescription(library(file));
    const std::string text = vehicleDescriptionToText(a);
    const VehicleDescription b = vehicleDescriptionFromText(text, "mem");
    EXPECT_EQ(vehicleDescriptionToText(b), text) << file;
    EXPECT_EQ(vehicleParamsToText(b.params), vehicleParamsToText(a.params)) << file;
    EXPECT_EQ(b.quadfdi_motor_of_autopilot_motor, a.quadfdi_motor_of_autopilot_motor) << file;
    EXPECT_EQ(b.name, a.name);
  }
}

TEST(VehicleFile, SmallAsymmetryIsSymmetrisedToTheMeans) {
  const VehicleDescription d = vehicleDescriptionFromText(replaced(kValid, "x = 0.13\ny = 0.21", "x = 0.131\ny = 0.212"), "q");
  EXPECT_NEAR(d.params.pitchLever(), (0.131 + 3 * 0.13) / 4, 1e-15);
  EXPECT_NEAR(d.params.rollLever(), (0.212 + 3 * 0.21) / 4, 1e-15);
}

TEST(VehicleFile, RefusalsNameFileLineAndWhy) {
  EXPECT_EQ(refusal(kValid), test::kAccepted);
  // Asymmetric rotor positions (iris's raw 0.22 / 0.20 on the front arms, 4.8 %).
  std::string e = refusal(replaced(replaced(kValid, "x = 0.13\ny = 0.21", "x = 0.13\ny = 0.22"), "x = 0.13\ny = -0.21",
                                   "x = 0.13\ny = -0.22"));
  EXPECT_EQ(e.rfind("quad.toml:16: asymmetric rotor positions: motor 1", 0), 0u) << e;
  // Centre of mass offset: every rotor shifted 1 cm forward.
  std::string shifted = kValid;
  shifted = replaced(shifted, "x = 0.13\ny = 0.21", "x = 0.14\ny = 0.21");
  shifted = replaced(shifted, "x = -0.13\ny = -0.21", "x = -0.12\ny = -0.21");
  shifted = replaced(shifted, "x = 0.13\ny = -0.21", "x = 0.14\ny = -0.21");
  shifted = replaced(shifted, "x = -0.13\ny = 0.21", "x = -0.12\ny = 0.21");
  e = refusal(shifted);
  EXPECT_EQ(e.rfind("quad.toml:16: centre of mass offset", 0), 0u) << e;
  // Wrong spin pattern: diagonal rotors spinning opposite ways.
  e = refusal(replaced(kValid, "y = -0.21\nspin = \"ccw\"", "y = -0.21\nspin = \"cw\""));
  EXPECT_EQ(e.rfind("quad.toml:20: wrong spin pattern", 0), 0u) << e;
  // Every rotor spinning the same way: no yaw moment.
  e = refusal(replaced(replaced(kValid, "y = -0.21\nspin = \"cw\"", "y = -0.21\nspin = \"ccw\""), "y = 0.21\nspin = \"cw\"",
                       "y = 0.21\nspin = \"ccw\""));
  EXPECT_EQ(e.rfind("quad.toml:28: wrong spin pattern: motors 1 and 4 are neighbours and spin the same way", 0), 0u) << e;
  // Duplicate motor position.
  e = refusal(replaced(kValid, "x = -0.13\ny = 0.21", "x = 0.13\ny = 0.21"));
  EXPECT_EQ(e.rfind("quad.toml:28: motors 1 and 4 are both front-right", 0), 0u) << e;
  // Missing fields: a top-level one (points at the end of the file) and one in a motor section.
  e = refusal(replaced(kValid, "mass = 1.5\n", ""));
  EXPECT_EQ(e, "quad.toml:29: missing 'mass' ([kg])") << e;
  e = refusal(replaced(kValid, "x = -0.13\ny = 0.21\nspin = \"cw\"\n", "x = -0.13\ny = 0.21\n"));
  EXPECT_EQ(e.rfind("quad.toml:28: missing 'motor.4.spin'", 0), 0u) << e;
  // Bad number.
  e = refusal(replaced(kValid, "inertia_yy = 0.03", "inertia_yy = 0.03kg"));
  EXPECT_EQ(e, "quad.toml:7: 'inertia_yy' needs a finite number, got '0.03kg'");
  // Non-zero product of inertia, unknown key, plus frame, wrong frame, hover above max thrust.
  e = refusal(replaced(kValid, "inertia_zz = 0.05\n", "inertia_zz = 0.05\ninertia_xy = 1e-4\n"));
  EXPECT_EQ(e.rfind("quad.toml:9: non-zero product of inertia inertia_xy", 0), 0u) << e;
  e = refusal(replaced(kValid, "mass = 1.5", "mass = 1.5\nmas = 2"));
  EXPECT_EQ(e.rfind("quad.toml:6: unknown key 'mas'", 0), 0u) << e;
  e = refusal(replaced(kValid, "x = 0.13\ny = 0.21", "x = 0.0\ny = 0.21"));
  EXPECT_EQ(e.rfind("quad.toml:16: motor 1 lies on a body axis and motor 2 does not", 0), 0u) << e;
  e = refusal(replaced(kValid, "frame = \"frd\"", "frame = \"flu\""));
  EXPECT_EQ(e.rfind("quad.toml:4: frame must be \"frd\"", 0), 0u) << e;
  e = refusal(replaced(kValid, "max = 7.0", "max = 3.0"));
  EXPECT_EQ(e.rfind("quad.toml: invalid vehicle: hover thrust", 0), 0u) << e;
  e = refusal(replaced(kValid, "model_factor = 0.8", "model_factor = 1.2"));
  EXPECT_EQ(e.rfind("quad.toml: invalid vehicle: thrust_model_factor must lie in [0, 1]", 0), 0u) << e;
}

// kValid with every spin reversed: a props-out X.
std::string propsOut(std::string text) {
  for (int i = 0; i < 2; ++i) text = replaced(text, "spin = \"ccw\"", "spin = \"CW-\"");
  for (int i = 0; i < 2; ++i) text = replaced(text, "spin = \"cw\"", "spin = \"ccw\"");
  for (int i = 0; i < 2; ++i) text = replaced(text, "spin = \"CW-\"", "spin = \"cw\"");
  return text;
}

// ArduPilot's PLUS (AP_MotorsMatrix::setup_quad_matrix): 1 right and 2 left counter-clockwise,
// 3 front and 4 back clockwise, arms of 0.25 m.
std::string plusFrame(std::string text) {
  text = replaced(text, "x = 0.13\ny = 0.21", "x = 0.0\ny = 0.25");
  text = replaced(text, "x = -0.13\ny = -0.21", "x = 0.0\ny = -0.25");
  text = replaced(text, "x = 0.13\ny = -0.21", "x = 0.25\ny = 0.0");
  return replaced(text, "x = -0.13\ny = 0.21", "x = -0.25\ny = 0.0");
}

TEST(VehicleFile, PropsOutAndPlusFramesAreReadAsTheStandardXInTurnedAxes) {
  // Props-out: the standard X seen from axes turned 90°; the roll and pitch levers and inertias swap.
  const std::string props_out = replaced(propsOut(kValid), "inertia_yy = 0.03", "inertia_yy = 0.028");
  const VehicleDescription d = vehicleDescriptionFromText(props_out, "q");
  EXPECT_EQ(d.body_turn.eighths, 2);
  EXPECT_NEAR(d.params.rotor_x, 0.21, 1e-15);
  EXPECT_NEAR(d.params.rotor_y, 0.13, 1e-15);
  EXPECT_EQ(d.params.inertia_xx, 0.028);
  EXPECT_EQ(d.params.inertia_yy, 0.03);
  // PX4 motor 1, front-right spinning clockwise, is quadfdi's back-right (clockwise) in the turned
  // axes, and still named front-right for its pilot.
  EXPECT_EQ(d.quadfdi_motor_of_autopilot_motor, (std::array<int, 4>{2, 4, 1, 3}));
  for (int k = 0; k < 4; ++k) {
    const int q = d.quadfdi_motor_of_autopilot_motor[static_cast<std::size_t>(k)];
    EXPECT_EQ(d.autopilot_motor_of_quadfdi_motor[static_cast<std::size_t>(q - 1)], k + 1);
    EXPECT_EQ(d.rotors[static_cast<std::size_t>(k)].ccw, kYawSign[static_cast<std::size_t>(q - 1)] < 0) << "motor " << k + 1;
  }
  EXPECT_STREQ(motorPosition(d.quadfdi_motor_of_autopilot_motor[0], d.body_turn), "front-right");
  EXPECT_STREQ(motorPosition(d.quadfdi_motor_of_autopilot_motor[1], d.body_turn), "back-left");
  // The file form keeps the airframe's own axes.
  const VehicleDescription back = vehicleDescriptionFromText(vehicleDescriptionToText(d), "mem");
  EXPECT_EQ(vehicleParamsToText(back.params), vehicleParamsToText(d.params));
  EXPECT_EQ(back.body_turn.eighths, 2);
  EXPECT_NE(vehicleDescriptionToText(d).find("inertia_yy = 0.028"), std::string::npos);

  // A plus frame: an X in axes turned 45° one way or the other, as its spins say.
  const VehicleDescription plus = vehicleDescriptionFromText(plusFrame(kValid), "q");
  EXPECT_EQ(plus.body_turn.eighths, -1);
  EXPECT_NEAR(plus.params.rotor_x, 0.25 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(plus.params.rotor_y, 0.25 / std::sqrt(2.0), 1e-15);
  const char* const where[] = {"right", "left", "front", "back"};
  for (int k = 0; k < 4; ++k) {
    const int q = plus.quadfdi_motor_of_autopilot_motor[static_cast<std::size_t>(k)];
    EXPECT_STREQ(motorPosition(q, plus.body_turn), where[k]) << "motor " << k + 1;
    EXPECT_EQ(plus.rotors[static_cast<std::size_t>(k)].ccw, kYawSign[static_cast<std::size_t>(q - 1)] < 0) << "motor " << k + 1;
  }
  EXPECT_EQ(vehicleDescriptionFromText(plusFrame(propsOut(kValid)), "q").body_turn.eighths, 1);  // ArduPilot's PLUSREV
  // Turned 45°, unequal roll and pitch inertias would be a product of inertia.
  const std::string e = refusal(replaced(plusFrame(kValid), "inertia_yy = 0.03", "inertia_yy = 0.035"));
  EXPECT_EQ(e.rfind("quad.toml:6: a plus frame with inertia_xx and inertia_yy 15.4 % apart", 0), 0u) << e;
  // A plus frame with arms of two lengths is no X in any axes.
  const std::string stretched =
      refusal(replaced(replaced(plusFrame(kValid), "x = 0.25\ny = 0.0", "x = 0.28\ny = 0.0"), "x = -0.25\ny = 0.0", "x = -0.28\ny = 0.0"));
  EXPECT_EQ(stretched.rfind("quad.toml:", 0), 0u) << stretched;
  EXPECT_NE(stretched.find("for a plus frame every arm of one length"), std::string::npos) << stretched;
}

TEST(VehicleFile, OldParameterFilesStillLoadThroughLoadVehicleParams) {
  const VehicleParams p = loadVehicleParams(std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicle-example.toml");
  EXPECT_EQ(vehicleParamsToText(p), vehicleParamsToText(nominalParams()));
  EXPECT_FALSE(looksLikeVehicleDescription("base = \"nominal\"\nmass = 0.03\n"));
  EXPECT_TRUE(looksLikeVehicleDescription(kValid));
}

}  // namespace
}  // namespace quadfdi
