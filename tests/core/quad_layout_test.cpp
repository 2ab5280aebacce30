// The one rule that reads a quad's rotors (core/quad_layout.h): every X numbering, the props-out
// X, the plus frames either way round, and what is refused. The physics check is the yaw: in the
// turned axes, each rotor must spin as quadfdi's motor there does (kYawSign), whatever the frame.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/quad_layout.h"

using namespace quadfdi;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// Rotors as ArduPilot's frame tables give them: arm angle clockwise from the nose, +1 counter-clockwise.
std::array<RotorPlacement, 4> fromAngles(const std::array<int, 4>& angle, const std::array<int, 4>& spin) {
  std::array<RotorPlacement, 4> r{};
  for (std::size_t i = 0; i < 4; ++i) r[i] = {0.2 * std::cos(angle[i] * kDeg), 0.2 * std::sin(angle[i] * kDeg), spin[i]};
  return r;
}

// Each rotor sits where the turn says and spins as quadfdi's motor there (1 and 3 counter-clockwise).
void expectStandardXInTurnedAxes(const std::array<RotorPlacement, 4>& rotors, const QuadLayout& l) {
  ASSERT_EQ(l.status, QuadLayoutStatus::kOk);
  const double a = l.turn.radians();
  for (std::size_t i = 0; i < 4; ++i) {
    const int q = l.quadfdi_motor_of[i];
    EXPECT_EQ(l.rotor_of_quadfdi_motor[static_cast<std::size_t>(q - 1)], static_cast<int>(i) + 1);
    if (rotors[i].spin != 0) {
      EXPECT_EQ(rotors[i].spin, q == 1 || q == 3 ? 1 : -1) << "rotor " << i + 1;
    }
    // The turned position, by the turn's definition (FLU, counter-clockwise): v' = Rz(−α)·v.
    const double x = rotors[i].x_forward, y_left = -rotors[i].y_right;
    const double xt = std::cos(a) * x + std::sin(a) * y_left, yt_left = -std::sin(a) * x + std::cos(a) * y_left;
    EXPECT_EQ(quadfdiMotorAtFrd(xt, -yt_left), q) << "rotor " << i + 1;
    EXPECT_NEAR(l.turned[i].x_forward, xt, 1e-15);
    EXPECT_NEAR(l.turned[i].y_right, -yt_left, 1e-15);
  }
}

}  // namespace

TEST(QuadLayout, EveryArdupilotQuadFrameIsTheStandardXInItsTurnedAxes) {
  struct Frame {
    const char* name;
    std::array<int, 4> angle, spin;
    int eighths;   // the expected turn
    bool plus;
  };
  // AP_MotorsMatrix::setup_quad_matrix.
  const Frame frames[] = {
      {"X", {45, -135, -45, 135}, {1, 1, -1, -1}, 0, false},
      {"BF_X", {135, 45, -135, -45}, {-1, 1, 1, -1}, 0, false},
      {"DJI_X", {45, -45, -135, 135}, {1, -1, 1, -1}, 0, false},
      {"CW_X", {45, 135, -135, -45}, {1, -1, 1, -1}, 0, false},
      {"H", {45, -135, -45, 135}, {-1, -1, 1, 1}, 2, false},
      {"BF_X_REV", {135, 45, -135, -45}, {1, -1, -1, 1}, 2, false},
      {"PLUS", {90, -90, 0, 180}, {1, 1, -1, -1}, -1, true},
      {"PLUSREV", {90, -90, 0, 180}, {-1, -1, 1, 1}, 1, true},
  };
  for (const Frame& f : frames) {
    SCOPED_TRACE(f.name);
    const std::array<RotorPlacement, 4> rotors = fromAngles(f.angle, f.spin);
    const QuadLayout l = quadLayout(rotors);
    expectStandardXInTurnedAxes(rotors, l);
    EXPECT_EQ(l.turn.eighths, f.eighths);
    EXPECT_EQ(l.plus, f.plus);
    EXPECT_TRUE(l.spins_checked);
    EXPECT_EQ(bodyTurnNote(l).empty(), f.eighths == 0);
  }
  // Named for the pilot where they sit on the airframe: PLUS's motor 3 is the front one.
  const QuadLayout plus = quadLayout(fromAngles({90, -90, 0, 180}, {1, 1, -1, -1}));
  EXPECT_STREQ(motorPosition(plus.quadfdi_motor_of[2], plus.turn), "front");
  EXPECT_STREQ(motorPosition(plus.quadfdi_motor_of[0], plus.turn), "right");
  const QuadLayout h = quadLayout(fromAngles({45, -135, -45, 135}, {-1, -1, 1, 1}));
  EXPECT_STREQ(motorPosition(h.quadfdi_motor_of[0], h.turn), "front-right");
  EXPECT_STREQ(motorPosition(h.quadfdi_motor_of[3], h.turn), "back-right");
}

TEST(QuadLayout, UnknownSpinsAndRefusals) {
  // An X whose spins are not known is read as the standard X (PX4's default assumption), unchecked.
  const QuadLayout x = quadLayout(fromAngles({45, -135, -45, 135}, {0, 0, 0, 0}));
  EXPECT_EQ(x.status, QuadLayoutStatus::kOk);
  EXPECT_EQ(x.turn.eighths, 0);
  EXPECT_FALSE(x.spins_checked);
  // One known spin decides: a clockwise front-right rotor makes it props-out.
  const QuadLayout one = quadLayout(fromAngles({45, -135, -45, 135}, {-1, 0, 0, 0}));
  EXPECT_EQ(one.turn.eighths, 2);
  // A plus frame's turn depends on its spins: unknown is refused.
  EXPECT_EQ(quadLayout(fromAngles({90, -90, 0, 180}, {0, 0, 0, 0})).status, QuadLayoutStatus::kSpinsUnknown);
  // Diagonal rotors spinning differently; all four alike.
  QuadLayout l = quadLayout(fromAngles({45, -135, -45, 135}, {1, -1, -1, -1}));
  EXPECT_EQ(l.status, QuadLayoutStatus::kWrongSpinPattern);
  EXPECT_EQ(l.motor, 1);
  EXPECT_EQ(l.other, 2);
  l = quadLayout(fromAngles({45, -135, -45, 135}, {1, 1, 1, 1}));
  EXPECT_EQ(l.status, QuadLayoutStatus::kWrongSpinPattern);
  // Half on the axes (a V or a Y4 is neither an X nor a plus); two rotors in one quadrant; no arm.
  l = quadLayout(fromAngles({0, 180, 45, -135}, {1, 1, -1, -1}));
  EXPECT_EQ(l.status, QuadLayoutStatus::kMixedAxes);
  EXPECT_EQ(l.motor, 1);
  EXPECT_EQ(l.other, 3);
  l = quadLayout(fromAngles({45, 50, -45, 135}, {1, 1, -1, -1}));
  EXPECT_EQ(l.status, QuadLayoutStatus::kDuplicateQuadrant);
  EXPECT_EQ(l.motor, 1);
  EXPECT_EQ(l.other, 2);
  std::array<RotorPlacement, 4> centre = fromAngles({45, -135, -45, 135}, {1, 1, -1, -1});
  centre[3] = {0.0, 0.0, -1};
  EXPECT_EQ(quadLayout(centre).status, QuadLayoutStatus::kRotorAtCentre);
  // A rotor 1° off an axis is on it; 3° off, it is read as an X's corner (its source checks the symmetry).
  EXPECT_TRUE(quadLayout(fromAngles({91, -89, 1, 179}, {1, 1, -1, -1})).plus);
  EXPECT_EQ(quadLayout(fromAngles({93, -87, 3, 183}, {1, 1, -1, -1})).status, QuadLayoutStatus::kOk);
}
