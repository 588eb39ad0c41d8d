// The four disk states and K_t (tracking/fading.h): Eq. 5 and 6 and the
// flow rule; the retire causes counted by rule and age.
#include <gtest/gtest.h>

#include <string>

#include "fluidtex/tracking/fading.h"
#include "fluidtex/tracking/tracker.h"

namespace fluidtex {
namespace {

// --- Fading: Eq. 5 and Eq. 6 ------------------------------------------------

TEST(Fading, FlowFadesWithinTheTimeTheFlowCarriesAPatchOneRadius) {
  // τ = 10, ρ = 0 (Eq. 6: 0.1 per frame); a centre moving 0.25 d per frame
  // fades in 4 frames, one moving 0.05 d per frame at Eq. 6's pace.
  auto frames = [](DiskState s, double motion) {
    double kt = s == DiskState::FadingIn ? 0.0 : 1.0;
    for (int n = 1;; ++n) {
      const FadeResult r = fade_step(s, kt, 0, 10, Fading::Flow, motion);
      if (r.remove || r.state == DiskState::Active) return n;
      kt = r.kt;
    }
  };
  EXPECT_EQ(frames(DiskState::FadingIn, 0.25), 4);
  EXPECT_EQ(frames(DiskState::FadingOutDistorted, 0.25), 4);
  EXPECT_EQ(frames(DiskState::FadingIn, 0.05), 10);
  EXPECT_EQ(frames(DiskState::FadingOutClose, 0.0), 10);
}

TEST(Fading, DensityFadesFasterAndRemovesAtZero) {
  // Fade-in over τ = 10 frames with ρ = 0: 10 steps; with ρ = 4: 2 steps.
  auto frames_to_active = [](int rho, Fading fading) {
    DiskState s = DiskState::FadingIn;
    double kt = 0.0;
    int n = 0;
    while (s == DiskState::FadingIn) {
      const FadeResult r = fade_step(s, kt, rho, 10, fading);
      s = r.state, kt = r.kt, ++n;
    }
    EXPECT_DOUBLE_EQ(kt, 1.0);
    return n;
  };
  EXPECT_EQ(frames_to_active(0, Fading::Density), 10);
  EXPECT_EQ(frames_to_active(4, Fading::Density), 2);
  EXPECT_EQ(frames_to_active(4, Fading::Linear), 10);  // Eq. 5 ignores ρ
  EXPECT_EQ(frames_to_active(4, Fading::Flow), 2);     // still liquid: Eq. 6
  // Eq. 6 fade-out: 1 − (t − t_k)(ρ + 1)/τ.
  FadeResult r = fade_step(DiskState::FadingOutClose, 1.0, 1, 10, Fading::Density);
  EXPECT_NEAR(r.kt, 0.8, 1e-12);
  EXPECT_FALSE(r.remove);
  // A very large ρ would make K_t negative: removed at once.
  r = fade_step(DiskState::FadingOutDistorted, 1.0, 50, 10, Fading::Density);
  EXPECT_TRUE(r.remove);
  r = fade_step(DiskState::FadingOutClose, 0.1, 0, 10, Fading::Density);
  EXPECT_TRUE(r.remove);  // reaches exactly 0
  r = fade_step(DiskState::Active, 1.0, 7, 10, Fading::Density);
  EXPECT_EQ(r.state, DiskState::Active);
  EXPECT_DOUBLE_EQ(r.kt, 1.0);
}

TEST(Fading, AFloorOnTheRateShortensTheFadeButNeverSlowsIt) {
  // The sink rule's floor (a sunk patch goes as fast as its surface): K_t
  // falls by the larger of Eq. 6's rate and the floor.
  FadeResult r = fade_step(DiskState::FadingOutClose, 1.0, 0, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_NEAR(r.kt, 0.65, 1e-12);
  r = fade_step(DiskState::FadingOutClose, 1.0, 4, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_NEAR(r.kt, 0.5, 1e-12);  // Eq. 6's (ρ + 1)/τ is faster
  r = fade_step(DiskState::FadingOutClose, 0.3, 0, 10, Fading::Flow, 0.0, 0.35);
  EXPECT_TRUE(r.remove);
}

TEST(RetireCauses, CountsAndAgeBuckets) {
  EXPECT_EQ(age_bucket(0), 0);
  EXPECT_EQ(age_bucket(1), 0);
  EXPECT_EQ(age_bucket(2), 1);
  EXPECT_EQ(age_bucket(7), 2);
  EXPECT_EQ(age_bucket(8), 3);
  EXPECT_EQ(age_bucket(31), 4);
  EXPECT_EQ(age_bucket(32), 5);
  EXPECT_EQ(age_bucket(1000), 5);
  const auto counts =
      retired_counts({{1, RetireCause::Quality, 3}, {2, RetireCause::Quality, 40}, {5, RetireCause::TooClose, 0}});
  auto get = [&](const std::string& k) {
    for (const auto& [key, n] : counts)
      if (key == k) return n;
    ADD_FAILURE() << "no key " << k;
    return -1.0;
  };
  EXPECT_EQ(counts.size(), static_cast<std::size_t>(kRetireCauses - 1 + kAgeBuckets));
  EXPECT_EQ(get("retired_quality"), 2);
  EXPECT_EQ(get("retired_too_close"), 1);
  EXPECT_EQ(get("retired_flipped"), 0);
  EXPECT_EQ(get("retired_age_0_1"), 1);
  EXPECT_EQ(get("retired_age_2_3"), 1);
  EXPECT_EQ(get("retired_age_32_up"), 1);
}

}  // namespace
}  // namespace fluidtex
