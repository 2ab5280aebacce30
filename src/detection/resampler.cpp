#include "detection/resampler.h"

#include <cmath>

namespace quadfdi {

TelemetrySample Resampler::interpolate(const TelemetrySample& a, const TelemetrySample& b, double t) {
  const double s = (t - a.t) / (b.t - a.t);
  TelemetrySample out;
  out.t = t;
  for (int i = 0; i < 5; ++i) out.y[i] = a.y[i] + s * (b.y[i] - a.y[i]);
  const double dyaw = wrapAngle(b.y[5] - a.y[5]);  // the short way round
  out.y[5] = wrapAngle(a.y[5] + s * dyaw);
  for (std::size_t i = 0; i < 3; ++i) out.rates[i] = a.rates[i] + s * (b.rates[i] - a.rates[i]);
  out.u = a.u;  // the command logged at a holds until the next one
  return out;
}

}  // namespace quadfdi
