// Randomised flights (docs/data.md#randomisation): each trajectory draws its vehicle, the plant's
// errors against the description, the estimator's noise, lag and delay, the controller and its
// gains, and the manoeuvre, as a pure function of (seed, scenario index). Ranges are plain data,
// recorded in the model file; all-zero spreads and single-choice mixes give the paper's setting.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/vehicle_params.h"
#include "simulation/rng.h"
#include "simulation/sampling.h"
#include "simulation/sensor_model.h"
#include "simulation/wind.h"

namespace quadfdi {

// The plant's error against the described vehicle: uniform factors on the described values
// ({1, 1}: none; {1.25, 1.25}: a fixed 25 % error, as the E7 test cells use).
struct ParameterSpread {
  Interval mass{1.0, 1.0};        // [-] plant mass = described · U(lo, hi) (payload, battery)
  Interval inertia{1.0, 1.0};     // [-] each diagonal element independently (payload placement)
  Interval thrust{1.0, 1.0};      // [-] thrust per command, all rotors alike (battery sag, wear)
  Interval yaw_moment{1.0, 1.0};  // [-] κ, the rotors' yaw moment per newton of thrust
  Interval motor_time_constant{0.0, 0.0};  // [s] absolute; {0, 0} keeps the description's value
};

// The flight controller's state estimate (simulation/sensor_model.h), drawn per flight.
struct SensorRanges {
  Interval position_std{0.0, 0.0};         // [m]
  Interval velocity_std{0.0, 0.0};         // [m/s]
  Interval attitude_std{0.0, 0.0};         // [rad]
  Interval rate_std{0.0, 0.0};             // [rad/s]
  Interval attitude_filter_tau{0.0, 0.0};  // [s]
  Interval rate_filter_tau{0.0, 0.0};      // [s]
  int delay_steps_max = 0;                 // [steps] delay drawn from U{0 … max}
  Interval estimate_error_tau{0.0, 0.0};   // [s] correlation time of the estimate errors (0: white)
};

enum class ManoeuvreKind { kHover, kPointToPoint, kCircle, kFigureEight };
const char* toString(ManoeuvreKind k);
bool parseManoeuvreKind(const std::string& text, ManoeuvreKind& kind);

// The air the flight meets (simulation/wind.h, docs/data.md#wind), drawn per flight, and the rotor
// drag it acts through. All {0, 0}: still air and no drag (the paper's model).
struct WindRanges {
  Interval rotor_drag{0.0, 0.0};      // [1/s] linear rotor drag per unit mass: plant linear_drag = this · mass
  Interval mean_speed{0.0, 0.0};      // [m/s] steady wind, from a uniform direction
  Interval turbulence_std{0.0, 0.0};  // [m/s] horizontal std of the continuous turbulence
  Interval turbulence_tau{1.0, 1.0};  // [s] its correlation time (> 0)
  Interval gust_rate{0.0, 0.0};       // [1/s] discrete gusts per second
  Interval gust_peak{0.0, 0.0};       // [m/s] largest gust peak
  Interval gust_duration{1.0, 1.0};   // [s] rise and fall of one gust (> 0)

  bool enabled() const { return rotor_drag.hi > 0.0; }
};

// Relative weights (≥ 0, not all zero) of what is flown, and its size.
struct ManoeuvreMix {
  double hover = 1.0, point_to_point = 0.0, circle = 0.0, figure_eight = 0.0;  // [-] weights
  Interval speed{0.5, 2.0};   // [m/s] cruise speed (point-to-point peak, circle and figure-eight path speed)
  Interval size{0.5, 1.5};    // [m] point-to-point distance, circle radius, figure-eight half-width
  double max_lateral_accel = 4.9;  // [m/s²] paths are widened until v²/r ≤ this (0.5 g keeps tilt ≤ 27°)
  // How the nose moves. Autopilots' mission modes point it along the path (PX4 MPC_YAW_MODE "towards
  // waypoint", ArduPilot Copter WP_YAW_BEHAVIOR "face next waypoint") and pilots pan it; a
  // yaw turn splits the commands between the two spin directions, which a detector that never saw
  // one reads as a weak motor (docs/data.md#heading). 0 and 0: every flight holds yaw 0.
  double facing_velocity = 0.0;              // [-] share of moving manoeuvres flown nose along the path
  double yaw_sweep = 0.0;                    // [-] share of flights whose heading also sweeps sinusoidally
  Interval yaw_sweep_amplitude{0.5, 0.5};    // [rad] sweep amplitude A (control/reference.h)
  Interval yaw_sweep_period{4.0, 4.0};       // [s] sweep period P
  // [rad/s] a circle flown nose first turns its nose at most this fast, as autopilots slew their
  // mission yaw (control/reference.h: PX4 MPC_YAWRAUTO_MAX 45 °/s, ArduPilot ATC_SLEW_YAW 60 °/s by
  // default); tighter circles leave the nose behind the path. 0: no limit. Figure-eights are not slewed.
  double facing_velocity_yaw_rate_max = 0.0;
  bool headingEnabled() const { return facing_velocity > 0.0 || yaw_sweep > 0.0; }
};

// Controllers flown (relative weights) and the spread of their gains.
struct ControllerMix {
  double lqr = 1.0, pid = 0.0, cbf = 0.0;  // [-] weights
  Interval gain_scale{1.0, 1.0};           // [-] PID loop bandwidths and LQR speed multiplied by this
  // [-] weight of the geometric SE(3) controller (control/geometric.h); 0 in every shipped
  // training mix, so that E7 holds it out. Last, so that {lqr, pid, cbf, gain_scale} still reads.
  double geometric = 0.0;
};

// Synthetic quad-X airframes (docs/data.md#synthetic-airframes): `count` descriptions drawn once,
// from their own seed, by the scaling of real airframes, and flown beside the described vehicles so
// that training meets a continuum of sizes and control authorities instead of a handful of real
// airframes. Each is then a described vehicle like the others: its controllers are designed on it
// and the plant is drawn around it. The defaults are configs/randomisation-airframes.toml's, chosen
// from the library's and the held-out airframes (docs/data.md#synthetic-airframes).
struct AirframeRanges {
  int count = 0;                          // [-] airframes drawn; 0 = none
  std::uint64_t seed = 1;                 // [-] the same seed and ranges give the same airframes
  double share = 0.5;                     // [-] fraction of flights flown on a synthetic airframe
  Interval mass{0.025, 3.0};              // [kg] log-uniform: a Crazyflie (27 g) to a 3 kg 650-class
  Interval size_factor{0.12, 0.24};       // [m/kg^(1/3)] rotor distance from the centre = this · mass^(1/3):
                                          //   Crazyflie 0.15, racer 0.14, Iris 0.22, X500 0.20, Solo 0.18
  Interval aspect{0.75, 1.33};            // [-] rotor |x| / |y|, log-uniform (1: square X; racer 0.75)
  Interval inertia_factor{0.3, 0.6};      // [-] Ixx / (m·y²) and Iyy / (m·x²), drawn each: racer 0.33 / 0.50,
                                          //   Iris 0.44 / 1.15 (its short x, outside), X500 0.36, Crazyflie 0.58
  Interval yaw_inertia_ratio{0.8, 1.0};   // [-] Izz / (Ixx + Iyy): 0.81 (Solo) … 0.95 (Iris); a flat plate's is 1
  Interval hover_fraction{0.15, 0.65};    // [-] hover thrust / max thrust per motor: racer 0.15, Iris 0.52, X500 0.57
  Interval idle_fraction{0.0, 0.03};      // [-] min thrust / max thrust: Crazyflie 0, X500 0.023
  Interval yaw_moment_coeff{0.005, 0.06}; // [m] κ, log-uniform: Crazyflie 0.006, racer 0.022, Iris 0.06
  Interval motor_time_constant{0.0, 0.035};  // [s] the plant's is redrawn by ParameterSpread when that is set

  bool enabled() const { return count > 0; }
};

struct Randomisation {
  // The described vehicles (the controllers' design models); the plant is drawn around one of them.
  std::vector<VehicleParams> vehicles;
  std::vector<std::string> vehicle_names;  // for reports, parallel to `vehicles`
  AirframeRanges airframes;                // synthetic descriptions flown beside `vehicles`
  ParameterSpread parameters;
  SensorRanges sensors;
  ManoeuvreMix manoeuvres;
  ControllerMix controllers;
  Interval preroll_seconds{0.0, 0.0};  // [s] healthy flight before the first recorded sample
  WindRanges wind;

  bool enabled() const { return !vehicles.empty(); }
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const AirframeRanges& a);
std::string validate(const Randomisation& r);

// The synthetic airframes of `a`, a pure function of it (each valid: validate(VehicleParams)).
std::vector<VehicleParams> drawAirframes(const AirframeRanges& a);
// Every described vehicle a flight may draw: `vehicles`, then the synthetic airframes.
std::vector<VehicleParams> describedVehicles(const Randomisation& r);
// "airframe-7" for the 7th synthetic airframe (index past `vehicles`), else the vehicle's name.
std::string describedVehicleName(const Randomisation& r, std::size_t index);

// Every flight's pre-roll `seconds` longer, its other draws unchanged: the pre-roll is one uniform
// draw of its interval, so shifting both ends keeps each flight's draw stream (the flyability
// probe, which flies the pre-roll too, may then redraw a marginal flight).
void delayPreroll(Randomisation& r, double seconds);

enum class DrawnController { kLqr, kPid, kCbfQp, kGeometric };
const char* toString(DrawnController c);

struct ManoeuvreDraw {
  ManoeuvreKind kind = ManoeuvreKind::kHover;
  double speed = 0.0;      // [m/s]
  double size = 0.0;       // [m]
  double direction = 0.0;  // [rad] point-to-point: heading of the path in the world frame
  bool facing_velocity = false;      // nose along the path (not for hover)
  double facing_yaw_rate_max = 0.0;  // [rad/s] a nose-first circle's slew limit (ManoeuvreMix); 0: none
  double yaw_sweep_amplitude = 0.0;  // [rad] 0: no sweep
  double yaw_sweep_period = 1.0;     // [s]
};

// One flight's draw.
struct FlightDraw {
  int vehicle = 0;            // index into describedVehicles(): Randomisation::vehicles, then the airframes
  VehicleParams plant;        // the vehicle flown: the description with the drawn errors
  double thrust_gain = 1.0;   // [-] thrust the rotors produce per newton commanded, all alike
  SensorModelConfig sensors;  // the estimator
  DrawnController controller = DrawnController::kLqr;
  double gain_scale = 1.0;    // [-]
  ManoeuvreDraw manoeuvre;
  int preroll_steps = 0;      // [steps]
  WindConfig wind;            // the flight's air; its drag is plant.linear_drag
};

// Draws one flight from `rng` (its own stream: the caller seeds it from (seed, scenario index)).
// `described` is describedVehicles(r), made once by the caller.
FlightDraw drawFlight(const Randomisation& r, const std::vector<VehicleParams>& described, double dt, Rng& rng);
FlightDraw drawFlight(const Randomisation& r, double dt, Rng& rng);

}  // namespace quadfdi
