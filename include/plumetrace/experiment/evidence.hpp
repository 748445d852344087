#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/experiment/stats.hpp"

namespace plumetrace {

/// One experiment set: an algorithm with one varied parameter (docs/experiments.md).
struct SetStats {
  std::string name;                ///< "A".."I"
  std::string algorithm;           ///< "casting", "surge-spiral", "surge-cast"
  std::string key;                 ///< varied config key, e.g. "casting.beta_deg"
  std::vector<double> values;      ///< axis values in increasing order
  std::vector<PointStats> points;  ///< one per value
  int fixed_index = -1;            ///< index of the paper's fixed value in `values`, -1 if absent
};

/// The evidence library every study decides with: the tests of a part and their margins, the
/// pooled groups of points, fits and spreads, and the wording of their figures (docs/claims.md,
/// "The statistics", "The tests applied to each part", "Margins", "Evidence strings").
namespace evidence {

// --- the outcome of a test

/// What the data say of one part: supported (yes), contradicted (no), or neither beyond noise.
enum class Support { kYes, kNo, kUnclear };

/// Name of a support: "yes", "no", "unclear".
std::string_view support_name(Support s);

/// The outcome of one test: its support and its signed margin (docs/claims.md, "Margins"): how far
/// the interval lies on the claimed side of the threshold, in widths of the interval; >= 0 when
/// the test says yes (> 0 but exactly at an "at least" limit), < 0 otherwise, NaN when the
/// interval cannot be computed.
struct Test {
  Support support = Support::kUnclear;  ///< yes, no or unclear
  double margin = NAN;                  ///< signed distance from the threshold, in widths
};

/// The numbers a part was decided on (docs/claims.md, "Every verdict carries its effect and
/// interval"): the quantity tested, its 95% interval and the threshold the test held it against;
/// NaN where a test has no such number (claim 8's linearity has no interval).
struct Figures {
  double estimate = NAN;  ///< the point estimate of the tested quantity
  Interval interval;      ///< its 95% interval
  double threshold = NAN;  ///< the threshold (m, M or L) it was held against
};

/// One tested part: a test's outcome and the figures that decided it.
struct Part {
  Support support = Support::kUnclear;  ///< the test's support
  double margin = NAN;                  ///< the test's margin
  std::string text;  ///< the figures, ending in " -> yes", " -> no", " -> unclear"
  Figures figures;   ///< the same figures as numbers
};

/// A part from a test and its figures; the support's name is appended ("... -> yes").
Part part(const Test& test, const std::string& text, const Figures& figures = {});

// --- the tests

/// How the directional test reads an effect's interval e against its threshold m.
enum class DirectionalRule {
  /// yes when e.lo > m, no when e.hi < m: one threshold, so the verdict moves toward the truth
  /// as runs grow and never flips between yes and no (issue 23, "Rules that converge")
  kSingleThreshold,
  /// the rule of plumetrace 0.3.0: yes when e.lo > 0, no when e.hi < m; for a true effect between
  /// 0 and m it says no at few runs and yes at many
  kLegacy030,
};

/// Name of a directional rule: "single-threshold", "legacy-0.3.0".
std::string_view directional_rule_name(DirectionalRule rule);

/// A distance from a threshold (positive on the claimed side) in units of a width, the width
/// floored at 1e-6 (a degenerate interval gives a large, finite margin); NaN when either is NaN.
double in_widths(double distance, double width);

/// hi - lo of an interval.
double width(const Interval& i);

/// "The effect is positive" (e signed so that the claimed direction is positive), with m the
/// smallest effect worth the name, read by `rule`; margin (e.lo - m) / width for the single
/// threshold, e.lo / width for the 0.3.0 rule. NaN ends give unclear.
Test directional(const Interval& effect, double m, DirectionalRule rule);

/// "The effect is negligible" (two-sided): yes when the interval lies inside (-margin, margin),
/// no when it lies wholly outside.
Test within(const Interval& effect, double margin);

/// "The quantity is below the limit": yes when hi < limit, no when lo >= limit.
Test below(const Interval& value, double limit);

/// "The quantity is at least the limit": yes when lo >= limit, no when hi < limit.
Test at_least(const Interval& value, double limit);

/// The smallest of several margins: a conjunction is as close to failing as its weakest part.
/// NaN when any is NaN or there is none.
double weakest(const std::vector<double>& margins);

/// The conjunction of several tests: no when one says no, yes when all say yes; the weakest
/// margin (NaN when any is NaN).
Test all_of(const std::vector<Test>& tests);

/// The support of a conjunction of parts: no as soon as one part says no, yes when every part
/// says yes, unclear otherwise and when there is no part.
Support combine(const std::vector<Part>& parts);

/// What the parts of one claim decide.
struct Decision {
  Support support = Support::kUnclear;  ///< the parts combined
  std::string evidence;                 ///< a preamble, then each part's figures, "; " between
  std::vector<Part> parts;              ///< the tested parts, in evidence order
  double margin = NAN;                  ///< the weakest part's margin; NaN when a part's is NaN
};

/// The decision of the parts; the evidence is an optional preamble, then each part's figures.
Decision decide(const std::vector<Part>& parts, const std::string& preamble = "");

/// An unclear decision without parts, its evidence saying why (a missing set, say).
Decision unclear_because(const std::string& problem);

// --- the wording of the figures (docs/claims.md, "Evidence strings")

/// printf into a string of at most 511 characters.
template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, pattern, args...);
  return buf;
}

/// A number with three decimals ("0.123"); "n/a" for NaN.
std::string num(double v);

/// A fraction as a signed percentage with one decimal ("+12.3%"); "n/a" for NaN.
std::string pct(double v);

/// A fraction as a whole percentage ("12%").
std::string margin_pct(double v);

/// An interval with three decimals: "[0.100, 0.200]".
std::string interval_text(const Interval& i);

/// An interval of fractions as signed percentages: "[-0.4%, +2.0%]".
std::string pct_interval_text(const Interval& i);

/// The strings joined with `sep` between them.
std::string join(const std::vector<std::string>& parts, const char* sep);

/// An axis value as printf's %g writes it ("0.614").
std::string value_text(double v);

// --- rates, means and their differences

/// -hi, -lo: the same effect signed the other way.
Interval negate(const Interval& i);

/// Both ends times f; NaN ends unless f is finite and positive.
Interval scaled(const Interval& i, double f);

/// k successes of n runs.
struct Rate {
  std::int64_t k = 0;  ///< successes
  std::int64_t n = 0;  ///< runs
  /// k / n; NaN when n = 0.
  double p() const { return n > 0 ? static_cast<double>(k) / static_cast<double>(n) : NAN; }
  /// Wilson 95% interval; NaN ends when n = 0.
  Interval ci() const { return n > 0 ? wilson_interval(k, n) : Interval{}; }
};

/// "k/n = p [lo, hi]".
std::string describe(const Rate& r);

/// "mean [lo, hi] (n=N)", "mean (n=1)" or "no successful run".
std::string describe(const MeanCi& m);

/// p_a - p_b with Newcombe's interval.
Interval rate_difference(const Rate& a, const Rate& b);

/// (mean_a - mean_b) / mean_ref with Welch's interval scaled by the reference mean.
Interval relative_difference(const MeanCi& a, const MeanCi& b, const MeanCi& ref);

/// (mean_a - mean_b) / mean_ref, the point estimate of relative_difference.
double relative_point(const MeanCi& a, const MeanCi& b, const MeanCi& ref);

// --- pooled groups of points

/// Points of one or more sets, pooled: their runs' successes and their successful runs'
/// overheads (docs/claims.md, "Pooling").
struct Group {
  std::string label;  ///< e.g. "A beta 5-20", "D+E+F"
  Rate rate;          ///< successes of runs
  MeanCi overhead;    ///< mean overhead of the successful runs, exactly as of the pooled runs
};

/// Short name of a set's varied parameter: "casting.beta_deg" -> "beta".
std::string symbol(const SetStats& s);

/// The number of values of a set.
int size_of(const SetStats& s);

/// first, first + 1, ..., end - 1.
std::vector<int> indices(int first, int end);

/// The lower half of a set's axis (the middle value of an odd count in neither half).
std::vector<int> lower_half(const SetStats& s);

/// The upper half of a set's axis (the middle value of an odd count in neither half).
std::vector<int> upper_half(const SetStats& s);

/// The points at `idx` of one set pooled, labelled "SET symbol first-last".
Group pool(const SetStats& s, const std::vector<int>& idx);

/// Exactly the same statistics: with a shared master seed the fixed-value points of an
/// algorithm's sets are the same configuration and so the same runs.
bool same_runs(const PointStats& a, const PointStats& b);

/// Which points of a set pool_sets takes.
enum class Points { kAll, kFixedOnly };

/// Points of several sets pooled, and how many distinct fixed-value points they hold.
struct PooledSets {
  Group group;             ///< labelled by the sets' names, "D+E+F"
  int distinct_fixed = 0;  ///< fixed-value points taken (each repeat counted once)
};

/// Pools the points of several sets (all, or the fixed-value ones only); a set's fixed-value
/// point that repeats one already taken (same_runs) is counted once.
PooledSets pool_sets(const std::vector<const SetStats*>& sets, Points which);

/// The thirds of a set's axis pooled: values [0, n/3), [n/3, 2n/3), [2n/3, n).
std::vector<Group> thirds(const SetStats& s);

// --- fits and spreads

/// Least-squares line through the overheads of the successful runs against the parameter,
/// computed from each point's n, mean and standard deviation (points with n >= 2), with the
/// lack-of-fit F test against pure error.
struct LineFit {
  bool ok = false;             ///< a line was fitted: >= 3 points, a finite slope, level > 0
  int points = 0;              ///< points used
  std::int64_t n = 0;          ///< successful runs used
  double slope = NAN;          ///< overhead per unit of the parameter
  Interval slope_ci;           ///< Student t 95% interval of the slope
  double level = NAN;          ///< fitted overhead at the smallest value used
  double span = NAN;           ///< largest minus smallest value used
  double lack_of_fit_p = NAN;  ///< upper tail of the lack-of-fit F statistic
  double max_deviation = NAN;  ///< largest |point mean - line|
};

/// The least-squares line through a set's overheads (LineFit).
LineFit fit_line(const SetStats& s);

/// Largest minus smallest of several quantities, with bounds from their intervals.
struct Spread {
  double point = NAN;  ///< largest minus smallest value
  Interval bounds;     ///< [max(0, largest lo - smallest hi), largest hi - smallest lo]
};

/// The spread of values with their intervals; NaN unless there are two or more values and
/// every interval is finite.
Spread spread(const std::vector<double>& values, const std::vector<Interval>& intervals);

}  // namespace evidence
}  // namespace plumetrace
