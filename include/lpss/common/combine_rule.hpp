// How two touching bodies' friction (or restitution) coefficients make the contact's: engines differ,
// and a scene says which it means.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lpss {

enum class CombineRule : std::uint8_t {
    product,         ///< a * b: Bullet's rule (two frictions of 0.5 make 0.25), the default
    geometric_mean,  ///< sqrt(a * b): Jolt's friction rule; equal coefficients stay what they are
    average,         ///< (a + b) / 2: PhysX's default
    min,
    max,
};

/// The contact's coefficient from the two bodies'.
inline double combine(CombineRule rule, double a, double b) {
    switch (rule) {
        case CombineRule::geometric_mean:
            return std::sqrt(a * b);
        case CombineRule::average:
            return 0.5 * (a + b);
        case CombineRule::min:
            return std::min(a, b);
        case CombineRule::max:
            return std::max(a, b);
        case CombineRule::product:
            break;
    }
    return a * b;
}

}  // namespace lpss
