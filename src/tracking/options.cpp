#include "fluidtex/tracking/options.h"

#include "fluidtex/util/error.h"

namespace fluidtex {

void TrackingOptions::validate() const { check_options(*this); }

TrackingOptions TrackingOptions::resolved(double first_frame_diagonal) const {
  TrackingOptions r = *this;
  if (!r.radius) r.radius = 0.05 * first_frame_diagonal;
  if (!r.max_projection) r.max_projection = 0.25 * *r.radius;
  if (!r.thickness) r.thickness = 0.25 * *r.radius;
  return r;
}

double TrackingOptions::length(const std::optional<double>& v, const char* name) {
  if (!v) throw InternalError(std::string("tracking option '") + name + "' used before it was resolved");
  return *v;
}

}  // namespace fluidtex
