#pragma once

// The elementary functions of the model, the same bits on every machine.
//
// why: the C library's exp, log, sin, atan2, hypot, pow... differ between machines in their last
// bits: glibc on x86-64 picks other versions of them on a processor with FMA, and glibc on
// 64-bit ARM gives other bits again for atan2, pow and hypot (docs/reliability.md, "Same bits on
// every machine"). One such bit, in a robot's heading, changes a whole run. These are computed
// with IEEE +, -, *, / and sqrt only (each correctly rounded) and integer operations, compiled
// without fused multiply-adds (-ffp-contract=off), in the library (never inlined into code built
// with other flags). Accuracy: within a few units in the last place (tests/core/math_test.cpp
// measures each against the C library); sin, cos and tan lose accuracy beyond |x| = 2^30 but
// stay the same on every machine. Special values (NaN, infinities, zeros) follow C's rules.

namespace plumetrace::math {

/// e^x.
double exp(double x);
/// e^x - 1, accurate near 0.
double expm1(double x);
/// Natural logarithm (NaN for x < 0, -inf at 0).
double log(double x);
/// log(1 + x), accurate near 0.
double log1p(double x);
/// x^y.
double pow(double x, double y);
/// Sine of x (rad).
double sin(double x);
/// Cosine of x (rad).
double cos(double x);
/// Tangent of x (rad).
double tan(double x);
/// Arc tangent (rad), in [-pi/2, pi/2].
double atan(double x);
/// The angle of (x, y) (rad), in [-pi, pi].
double atan2(double y, double x);
/// Arc sine (rad), in [-pi/2, pi/2]; NaN for |x| > 1.
double asin(double x);
/// sqrt(x^2 + y^2) without overflow or underflow on the way.
double hypot(double x, double y);
/// Hyperbolic sine.
double sinh(double x);
/// Inverse hyperbolic sine.
double asinh(double x);

}  // namespace plumetrace::math
