// The dielectric Fresnel of microfacet.h against the textbook s / p form in double.
#include <doctest/doctest.h>

#include <cmath>

#include "microfacet.h"

namespace {

double fresnel_sp(double c, double eta) {
    const double ct = std::sqrt(1 - (1 - c * c) / (eta * eta));
    const double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace

TEST_CASE("the dielectric Fresnel is the unpolarised s / p mean, f0 at normal incidence, 1 at grazing") {
    for (float f0 : {0.02f, 0.04f, 0.08f, 0.3f, 0.9f}) {
        const float eta = gw::dielectric_eta(f0);
        CHECK(gw::fresnel_dielectric(1.0f, eta) == doctest::Approx(f0).epsilon(1e-4));
        CHECK(gw::fresnel_dielectric(0.0f, eta) == doctest::Approx(1.0f));
        for (float c = 0.05f; c < 1.0f; c += 0.05f)
            CHECK(gw::fresnel_dielectric(c, eta) == doctest::Approx(fresnel_sp(c, eta)).epsilon(1e-4));
    }
}

TEST_CASE("the dielectric Fresnel stays finite where the IOR rounds to 1") {
    for (float c : {0.0f, 1e-30f, 0.5f, 1.0f}) {
        const float f = gw::fresnel_dielectric(c, gw::dielectric_eta(1e-20f));
        CHECK(std::isfinite(f));
        CHECK(f >= 0.0f);
        CHECK(f <= 1.0f);
    }
}
