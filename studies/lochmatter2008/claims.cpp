#include "lochmatter2008/claims.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/experiment/evidence.hpp"

namespace plumetrace {

namespace {

// the claims are stated in the words of the evidence library (experiment/evidence.hpp)
using evidence::all_of;
using evidence::at_least;
using evidence::below;
using evidence::decide;
using evidence::Decision;
using evidence::describe;
using evidence::DirectionalRule;
using evidence::fit_line;
using evidence::format;
using evidence::Group;
using evidence::in_widths;
using evidence::indices;
using evidence::interval_text;
using evidence::join;
using evidence::LineFit;
using evidence::lower_half;
using evidence::margin_pct;
using evidence::negate;
using evidence::num;
using evidence::Part;
using evidence::part;
using evidence::pct;
using evidence::pct_interval_text;
using evidence::Points;
using evidence::pool;
using evidence::pool_sets;
using evidence::rate_difference;
using evidence::relative_difference;
using evidence::relative_point;
using evidence::scaled;
using evidence::size_of;
using evidence::Spread;
using evidence::spread;
using evidence::Support;
using evidence::symbol;
using evidence::Test;
using evidence::thirds;
using evidence::unclear_because;
using evidence::upper_half;
using evidence::value_text;
using evidence::weakest;
using evidence::width;
using evidence::within;

// Thresholds of the decision rules; docs/claims.md gives the reason for each. They were fixed
// before any data were looked at and must not be changed to make a claim hold.

// Success rates, absolute: "barely changes", "comparable" and "not the failure rate" tolerate
// changes smaller than this; under rules 0.3.0 it was also the m of directional success parts
// (a part contradicted when the data exclude a difference of this size in the claimed direction).
constexpr double kSuccessMargin = 0.10;
// Overheads, as a fraction of the reference group's mean: the m of directional overhead parts
// under rules 0.3.0 only, and the largest change "barely" and "comparable" tolerate.
constexpr double kMinOverheadEffect = 0.05;
constexpr double kNegligibleOverhead = 0.10;
// Words of single claims.
constexpr double kVirtuallyAll = 0.95;       // claim 1: success rate
constexpr double kBetaSplit = 20.0;          // claim 2: "beta > 20 deg" (deg)
constexpr double kAcceptable = 0.80;         // claim 2: acceptable success rate
constexpr double kAlmostAlwaysFails = 0.20;  // claim 4: success rate below this
constexpr double kSlightEffect = 0.01;       // claim 6 under rules 0.3.0: its m
constexpr double kLowRate = 0.50;            // claim 8: rise over the range / overhead
constexpr double kLackOfFitAlpha = 0.05;     // claim 8: lack-of-fit test level
constexpr double kMaxNonlinearity = 0.25;    // claim 8: largest deviation / rise
constexpr double kMuchLess = 0.50;           // claim 11: "much less" = less than half

// What a rule set decides differently (docs/claims.md, "Rules 0.4: rules that converge"): how a
// directional part reads its effect against its m, the m of each kind of directional part, and
// what claim 11's importance measures.
struct RuleSet {
  DirectionalRule directional;  // how e is read against m
  double success_m;             // directional success parts
  double overhead_m;            // directional overhead parts
  double slight_m;              // claim 6's "slightly lower"
  bool importance_of_overhead;  // claim 11: the overhead spread alone, else the larger spread
};

// rules 0.3.0: yes above 0, no below m, with m from the thresholds above
constexpr RuleSet kRules030{DirectionalRule::kLegacy030, kSuccessMargin, kMinOverheadEffect,
                            kSlightEffect, false};
// rules 0.4: one threshold m = 0 for every directional part, the paper stating only directions;
// claim 11 on overhead, the paper's measure of "performance"
constexpr RuleSet kRules04{DirectionalRule::kSingleThreshold, 0.0, 0.0, 0.0, true};

const RuleSet& rule_set(ClaimRules rules) {
  return rules == ClaimRules::kRules030 ? kRules030 : kRules04;
}

// A directional part's test under a rule set, and its figures.
Test directional(const Interval& effect, double m, const RuleSet& r) {
  return evidence::directional(effect, m, r.directional);
}
evidence::Figures figures(double estimate, const Interval& interval, double threshold) {
  return {estimate, interval, threshold};
}

Verdict verdict_of(Support s) {
  return s == Support::kYes  ? Verdict::kHolds
         : s == Support::kNo ? Verdict::kDoesNotHold
                             : Verdict::kUnclear;
}

// access to the sets

using Sets = std::map<std::string, SetStats>;

std::string check_set(const SetStats& s) {
  if (s.values.empty()) return "set " + s.name + " has no values";
  if (s.values.size() != s.points.size()) {
    return format("set %s is malformed (%zu values, %zu points)", s.name.c_str(), s.values.size(),
                  s.points.size());
  }
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    if (!std::isfinite(s.values[i]) || (i > 0 && !(s.values[i] > s.values[i - 1]))) {
      return "set " + s.name + " has values that are not finite and increasing";
    }
  }
  if (s.fixed_index < -1 || s.fixed_index >= size_of(s)) {
    return "set " + s.name + " has a fixed index out of range";
  }
  return "";
}

// The named sets, or a message naming those missing or malformed.
struct Needed {
  std::vector<const SetStats*> sets;
  std::string problem;
};

Needed need(const Sets& sets, std::initializer_list<const char*> names, int min_values = 2) {
  Needed out;
  std::vector<std::string> problems;
  std::vector<std::string> missing;
  for (const char* name : names) {
    const auto it = sets.find(name);
    if (it == sets.end()) {
      missing.push_back(name);
      continue;
    }
    if (std::string p = check_set(it->second); !p.empty()) {
      problems.push_back(p);
    } else if (size_of(it->second) < min_values) {
      problems.push_back(
          format("set %s has %d values, needs at least %d", name, size_of(it->second), min_values));
    } else {
      out.sets.push_back(&it->second);
    }
  }
  if (!missing.empty()) {
    problems.insert(problems.begin(),
                    (missing.size() == 1 ? "missing set " : "missing sets ") + join(missing, ", "));
  }
  out.problem = join(problems, "; ");
  return out;
}

// recurring parts

// "Overhead is higher in `high` than in `low`" (relative to `low`).
Part overhead_rises(const Group& low, const Group& high, double min_effect, const RuleSet& r,
                    const std::string& what) {
  const Interval rise = relative_difference(high.overhead, low.overhead, low.overhead);
  const double point = relative_point(high.overhead, low.overhead, low.overhead);
  return part(directional(rise, min_effect, r),
              what + ": " + low.label + " " + describe(low.overhead) + ", " + high.label + " " +
                  describe(high.overhead) + "; change " + pct(point) + " " +
                  pct_interval_text(rise),
              figures(point, rise, min_effect));
}

// "Success is lower in `low_success` than in `high_success`".
Part success_drops(const Group& high_success, const Group& low_success, double min_effect,
                   const RuleSet& r, const std::string& what) {
  const Interval drop = rate_difference(high_success.rate, low_success.rate);
  const double point = high_success.rate.p() - low_success.rate.p();
  return part(directional(drop, min_effect, r),
              what + ": " + high_success.label + " " + describe(high_success.rate) + ", " +
                  low_success.label + " " + describe(low_success.rate) + "; difference " +
                  num(point) + " " + interval_text(drop),
              figures(point, drop, min_effect));
}

// the claims

Decision claim1(const Sets& sets, const RuleSet& /*rules: no directional part*/) {
  const Needed n = need(sets, {"D", "E", "F"}, 1);
  if (!n.problem.empty()) return unclear_because(n.problem);
  const Group all = pool_sets(n.sets, Points::kAll).group;
  return decide({part(at_least(all.rate.ci(), kVirtuallyAll),
                      all.label + " success " + describe(all.rate) + " vs " + num(kVirtuallyAll),
                      figures(all.rate.p(), all.rate.ci(), kVirtuallyAll))});
}

Decision claim2(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"A"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& a = *n.sets[0];
  // the axis is in degrees when its key says so (casting.beta_deg), else in radians
  const double split = a.key.ends_with("_deg") ? kBetaSplit : deg_to_rad(kBetaSplit);
  std::vector<int> small, large;
  for (int i = 0; i < size_of(a); ++i) (a.values[i] <= split ? small : large).push_back(i);
  if (small.empty() || large.empty()) {
    return unclear_because("set A has no values on one side of beta = 20 deg");
  }
  const Group lo = pool(a, small), hi = pool(a, large);
  std::vector<Part> parts;
  parts.push_back(success_drops(hi, lo, r.success_m, r, "success lower at small beta"));
  parts.push_back(overhead_rises(lo, hi, r.overhead_m, r, "overhead lower at small beta"));
  parts.push_back(part(
      at_least(hi.rate.ci(), kAcceptable),
      "beta > 20 acceptable: " + hi.label + " " + describe(hi.rate) + " vs " + num(kAcceptable),
      figures(hi.rate.p(), hi.rate.ci(), kAcceptable)));
  // "only": no single value at or below 20 deg reaches an acceptable rate
  Test none{Support::kYes, INFINITY};
  int best = small.front();
  for (int i : small) {
    const Test s = below(a.points[i].success_ci, kAcceptable);
    if (s.support == Support::kNo ||
        (s.support == Support::kUnclear && none.support == Support::kYes)) {
      none.support = s.support;
    }
    none.margin = weakest({none.margin, s.margin});
    if (a.points[i].success_rate > a.points[best].success_rate) best = i;
  }
  const Group best_group = pool(a, {best});
  parts.push_back(part(none,
                       "no beta <= 20 acceptable: best " + best_group.label + " " +
                           describe(best_group.rate) + " vs " + num(kAcceptable),
                       figures(best_group.rate.p(), best_group.rate.ci(), kAcceptable)));
  return decide(parts);
}

Decision claim3(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"B"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& b = *n.sets[0];
  const Group lo = pool(b, lower_half(b)), hi = pool(b, upper_half(b));
  const Interval success_up = rate_difference(hi.rate, lo.rate);
  const Interval overhead_up = relative_difference(hi.overhead, lo.overhead, lo.overhead);
  // either success drops at the low end and overhead worsens at the high end, or the reverse
  const Test rising_test = all_of({directional(success_up, r.success_m, r),
                                   directional(overhead_up, r.overhead_m, r)});
  const Test falling_test = all_of({directional(negate(success_up), r.success_m, r),
                                    directional(negate(overhead_up), r.overhead_m, r)});
  const Support rising = rising_test.support, falling = falling_test.support;
  // why: either pattern will do, so the claim is as close to holding as the better pattern
  Test either{Support::kUnclear, std::isnan(rising_test.margin) || std::isnan(falling_test.margin)
                                     ? NAN
                                     : std::fmax(rising_test.margin, falling_test.margin)};
  if (rising == Support::kYes || falling == Support::kYes) either.support = Support::kYes;
  if (rising == Support::kNo && falling == Support::kNo) either.support = Support::kNo;
  std::string which = "neither pattern resolved";
  if (rising == Support::kNo && falling == Support::kNo) which = "neither pattern";
  if (rising == Support::kYes) which = "success drops at low d_lost, overhead worsens at high";
  if (falling == Support::kYes) which = "success drops at high d_lost, overhead worsens at low";
  return decide(
      {part(either, "success " + lo.label + " " + describe(lo.rate) + ", " + hi.label + " " +
                        describe(hi.rate) + "; change " + num(hi.rate.p() - lo.rate.p()) + " " +
                        interval_text(success_up) + "; overhead " + describe(lo.overhead) + " -> " +
                        describe(hi.overhead) + "; change " +
                        pct(relative_point(hi.overhead, lo.overhead, lo.overhead)) + " " +
                        pct_interval_text(overhead_up) + "; " + which)});
}

Decision claim4(const Sets& sets, const RuleSet& /*rules: no directional part*/) {
  const Needed n = need(sets, {"C"}, 7);
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& c = *n.sets[0];
  const int size = size_of(c);
  const Group low = pool(c, indices(0, 2));
  const Group mid = pool(c, indices(size / 2 - 1, size / 2 + 2));
  const Group top = pool(c, indices(size - 2, size));
  std::vector<Part> parts;
  parts.push_back(part(below(top.rate.ci(), kAlmostAlwaysFails),
                       "fails at the top: " + top.label + " success " + describe(top.rate) +
                           " vs " + num(kAlmostAlwaysFails),
                       figures(top.rate.p(), top.rate.ci(), kAlmostAlwaysFails)));
  const Interval ds = rate_difference(mid.rate, low.rate);
  parts.push_back(part(within(ds, kSuccessMargin),
                       "success barely changes: " + low.label + " " + describe(low.rate) + ", " +
                           mid.label + " " + describe(mid.rate) + "; change " +
                           num(mid.rate.p() - low.rate.p()) + " " + interval_text(ds) + " vs +-" +
                           num(kSuccessMargin),
                       figures(mid.rate.p() - low.rate.p(), ds, kSuccessMargin)));
  const Interval dov = relative_difference(mid.overhead, low.overhead, low.overhead);
  parts.push_back(part(within(dov, kNegligibleOverhead),
                       "overhead barely changes: " + describe(low.overhead) + " -> " +
                           describe(mid.overhead) + "; change " +
                           pct(relative_point(mid.overhead, low.overhead, low.overhead)) + " " +
                           pct_interval_text(dov) + " vs +-" + margin_pct(kNegligibleOverhead),
                       figures(relative_point(mid.overhead, low.overhead, low.overhead), dov,
                               kNegligibleOverhead)));
  return decide(parts);
}

Decision claim5(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"D"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& d = *n.sets[0];
  return decide({overhead_rises(pool(d, lower_half(d)), pool(d, upper_half(d)), r.overhead_m, r,
                                "overhead lower at small d_gap")});
}

Decision claim6(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"E"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& e = *n.sets[0];
  const Group lo = pool(e, lower_half(e)), hi = pool(e, upper_half(e));
  const Interval fall = relative_difference(lo.overhead, hi.overhead, lo.overhead);
  const double point = relative_point(lo.overhead, hi.overhead, lo.overhead);
  return decide({part(directional(fall, r.slight_m, r),
                      "overhead lower at high d_lost: " + lo.label + " " + describe(lo.overhead) +
                          ", " + hi.label + " " + describe(hi.overhead) + "; decrease " +
                          pct(point) + " " + pct_interval_text(fall),
                      figures(point, fall, r.slight_m))});
}

Decision claim7(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"F"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& f = *n.sets[0];
  const Group lo = pool(f, lower_half(f)), hi = pool(f, upper_half(f));
  std::vector<Part> parts;
  parts.push_back(overhead_rises(lo, hi, r.overhead_m, r, "overhead higher at high sigma_a"));
  const Interval failure_rise = rate_difference(lo.rate, hi.rate);
  parts.push_back(part(below(failure_rise, kSuccessMargin),
                       "failure rate not raised: " + lo.label + " " + describe(lo.rate) + ", " +
                           hi.label + " " + describe(hi.rate) + "; success drop " +
                           num(lo.rate.p() - hi.rate.p()) + " " + interval_text(failure_rise) +
                           " vs " + num(kSuccessMargin),
                       figures(lo.rate.p() - hi.rate.p(), failure_rise, kSuccessMargin)));
  return decide(parts);
}

Decision claim8(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"G"}, 3);
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& g = *n.sets[0];
  std::vector<Part> parts;
  const LineFit fit = fit_line(g);
  if (!fit.ok) {
    parts.push_back(part(
        Test{}, format("too few points with >= 2 successful runs to fit a line (%d)", fit.points)));
  } else {
    // the fitted rise over the range, as a fraction of the overhead at its low end
    const double to_rise = fit.span / fit.level;
    const Interval rise = scaled(fit.slope_ci, to_rise);
    const std::string fit_text = format("line through %d points (n=%lld): overhead ", fit.points,
                                        static_cast<long long>(fit.n)) +
                                 num(fit.level) + " at d_cast " + value_text(g.values.front()) +
                                 ", rise over the range " + pct(fit.slope * to_rise) + " " +
                                 pct_interval_text(rise);
    parts.push_back(part(directional(rise, r.overhead_m, r), "grows: " + fit_text,
                         figures(fit.slope * to_rise, rise, r.overhead_m)));
    parts.push_back(part(below(rise, kLowRate),
                         "at a low rate: rise " + pct_interval_text(rise) + " vs " +
                             margin_pct(kLowRate),
                         figures(fit.slope * to_rise, rise, kLowRate)));
    const double rise_abs = std::fabs(fit.slope * fit.span);
    const double nonlinearity = fit.max_deviation / rise_abs;
    // why: no interval here; the margin is the better of the two ways to say yes, each as a
    // distance from its own limit (p-value above alpha, nonlinearity below its bound)
    Test linear{Support::kUnclear,
                std::fmax(fit.lack_of_fit_p - kLackOfFitAlpha, kMaxNonlinearity - nonlinearity)};
    if (std::isnan(fit.lack_of_fit_p)) linear.margin = NAN;
    if (fit.lack_of_fit_p >= kLackOfFitAlpha) linear.support = Support::kYes;
    if (fit.lack_of_fit_p < kLackOfFitAlpha) {
      linear.support = nonlinearity <= kMaxNonlinearity ? Support::kYes : Support::kNo;
    }
    parts.push_back(
        part(linear, "about linearly: lack-of-fit p = " + format("%.3g", fit.lack_of_fit_p) +
                         ", largest deviation " + num(fit.max_deviation) + " = " +
                         format("%.0f%%", 100.0 * nonlinearity) + " of the rise"));
  }
  const Group smallest = pool(g, {0});
  const Group rest = pool(g, indices(1, size_of(g)));
  parts.push_back(success_drops(rest, smallest, r.success_m, r, "very small d_cast fails more"));
  return decide(parts);
}

Decision claim9(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"I"});
  if (!n.problem.empty()) return unclear_because(n.problem);
  const SetStats& i = *n.sets[0];
  const Group lo = pool(i, lower_half(i)), hi = pool(i, upper_half(i));
  std::vector<Part> parts;
  parts.push_back(success_drops(lo, hi, r.success_m, r, "success lower at high sigma_a"));
  // "mainly": the relative drop of the success rate exceeds the relative rise of the overhead
  const Interval drop = scaled(rate_difference(lo.rate, hi.rate), 1.0 / lo.rate.p());
  const Interval rise = relative_difference(hi.overhead, lo.overhead, lo.overhead);
  Test mainly{Support::kUnclear, in_widths(drop.lo - rise.hi, width(drop) + width(rise))};
  if (drop.lo > rise.hi) mainly.support = Support::kYes;
  if (drop.hi < rise.lo) mainly.support = Support::kNo;
  parts.push_back(part(mainly, "mainly success: relative success drop " +
                                   pct((lo.rate.p() - hi.rate.p()) / lo.rate.p()) + " " +
                                   pct_interval_text(drop) + " vs overhead change " +
                                   pct(relative_point(hi.overhead, lo.overhead, lo.overhead)) +
                                   " " + pct_interval_text(rise) + " (" + describe(lo.overhead) +
                                   " -> " + describe(hi.overhead) + ")"));
  return decide(parts);
}

// The fixed-value point of one algorithm, pooled over those of its sets that are present.
struct AlgorithmAtFixed {
  std::string name;
  Group group;
  bool ok = false;
};

// `set_names` are the sets of one algorithm; it is named as its sets say (their first present),
// else by the sets ("A-C")
AlgorithmAtFixed at_fixed(const Sets& sets, std::initializer_list<const char*> set_names) {
  AlgorithmAtFixed out;
  std::vector<const SetStats*> with_fixed;
  for (const char* s : set_names) {
    if (const auto it = sets.find(s); it != sets.end() && out.name.empty()) {
      out.name = it->second.algorithm;
    }
    const Needed n = need(sets, {s}, 1);
    if (n.problem.empty() && n.sets[0]->fixed_index >= 0) with_fixed.push_back(n.sets[0]);
  }
  if (out.name.empty()) out.name = std::string(*set_names.begin()) + "-" + *(set_names.end() - 1);
  if (with_fixed.empty()) return out;
  const evidence::PooledSets fixed = pool_sets(with_fixed, Points::kFixedOnly);
  out.group = fixed.group;
  out.group.label =
      out.name + " (" + out.group.label + format(", %d distinct)", fixed.distinct_fixed);
  out.ok = true;
  return out;
}

Decision claim10(const Sets& sets, const RuleSet& r) {
  const AlgorithmAtFixed cast = at_fixed(sets, {"A", "B", "C"});
  const AlgorithmAtFixed spiral = at_fixed(sets, {"D", "E", "F"});
  const AlgorithmAtFixed surge = at_fixed(sets, {"G", "H", "I"});
  std::vector<std::string> missing;
  for (const auto* a : {&cast, &spiral, &surge}) {
    if (!a->ok) missing.push_back(a->name);
  }
  if (!missing.empty()) {
    return unclear_because("missing: no set with a fixed-value point for " + join(missing, ", ") +
                           " (sets A-C, D-F, G-I)");
  }
  const Group &c = cast.group, &sp = spiral.group, &sc = surge.group;
  std::vector<std::string> at;
  for (const Group* g : {&c, &sp, &sc}) {
    at.push_back(g->label + " " + describe(g->rate) + ", overhead " + describe(g->overhead));
  }
  // difference in success (first minus second) and relative change in overhead
  const auto success = [&r](const Group& a, const Group& b, const std::string& what) {
    const Interval d = rate_difference(a.rate, b.rate);
    const double point = a.rate.p() - b.rate.p();
    return part(directional(d, r.success_m, r), what + ": " + num(point) + " " + interval_text(d),
                figures(point, d, r.success_m));
  };
  const auto overhead = [&r](const Group& a, const Group& b, const std::string& what) {
    const Interval d = relative_difference(a.overhead, b.overhead, b.overhead);
    const double point = relative_point(a.overhead, b.overhead, b.overhead);
    return part(directional(d, r.overhead_m, r),
                what + ": " + pct(point) + " " + pct_interval_text(d),
                figures(point, d, r.overhead_m));
  };
  std::vector<Part> parts;
  const std::string &cn = cast.name, &spn = spiral.name, &scn = surge.name;
  parts.push_back(success(sp, c, cn + " below " + spn + " in success"));
  parts.push_back(success(sc, c, cn + " below " + scn + " in success"));
  parts.push_back(overhead(c, sp, cn + " above " + spn + " in overhead"));
  parts.push_back(overhead(c, sc, cn + " above " + scn + " in overhead"));
  const Interval ds = rate_difference(sc.rate, sp.rate);
  parts.push_back(
      part(within(ds, kSuccessMargin),
           scn + " comparable to " + spn + " in success: " + num(sc.rate.p() - sp.rate.p()) + " " +
               interval_text(ds) + " vs +-" + num(kSuccessMargin),
           figures(sc.rate.p() - sp.rate.p(), ds, kSuccessMargin)));
  const Interval dov = relative_difference(sc.overhead, sp.overhead, sp.overhead);
  parts.push_back(
      part(within(dov, kNegligibleOverhead),
           "in overhead: " + pct(relative_point(sc.overhead, sp.overhead, sp.overhead)) + " " +
               pct_interval_text(dov) + " vs +-" + margin_pct(kNegligibleOverhead),
           figures(relative_point(sc.overhead, sp.overhead, sp.overhead), dov,
                   kNegligibleOverhead)));
  return decide(parts, "at the fixed values: " + join(at, "; "));
}

// How much a set's parameter matters: the axis is cut into thirds (lowest, middle and highest
// values, pooled), and the spreads across the thirds of the success rate and of the mean overhead
// (relative to the set's pooled mean) are bounded from the thirds' intervals. The importance is
// the overhead spread (rules 0.4: the paper's "performance") or the larger of the two (0.3.0).
struct Importance {
  double point = NAN;
  Interval bounds;
  std::string text;
};

Importance importance(const SetStats& s, bool of_overhead) {
  std::vector<double> rates, means;
  std::vector<Interval> rate_cis, mean_cis;
  for (const Group& g : thirds(s)) {
    rates.push_back(g.rate.p());
    rate_cis.push_back(g.rate.ci());
    means.push_back(g.overhead.mean);
    mean_cis.push_back({g.overhead.lo, g.overhead.hi});
  }
  const Spread success = spread(rates, rate_cis);
  Spread overhead = spread(means, mean_cis);
  std::vector<MeanCi> parts;
  for (const PointStats& p : s.points) parts.push_back(p.overhead);
  const double ref = pooled_mean_ci(parts).mean;
  overhead.point /= ref;
  overhead.bounds = scaled(overhead.bounds, 1.0 / ref);

  Importance out;
  if (of_overhead) {
    // the success spread is reported, not tested
    out.point = overhead.point;
    out.bounds = overhead.bounds;
    out.text = s.name + " " + symbol(s) + ": overhead spread " + pct(overhead.point) + " " +
               pct_interval_text(overhead.bounds) + " (success spread " + num(success.point) +
               " " + interval_text(success.bounds) + ", not tested)";
    return out;
  }
  // the larger of the two spreads; an unknown upper end of either leaves the upper end unknown
  out.point = std::fmax(success.point, overhead.point);
  out.bounds.lo = std::fmax(success.bounds.lo, overhead.bounds.lo);
  out.bounds.hi = (std::isnan(success.bounds.hi) || std::isnan(overhead.bounds.hi))
                      ? NAN
                      : std::max(success.bounds.hi, overhead.bounds.hi);
  out.text = s.name + " " + symbol(s) + ": success spread " + num(success.point) + " " +
             interval_text(success.bounds) + ", overhead spread " + pct(overhead.point) + " " +
             pct_interval_text(overhead.bounds);
  return out;
}

Decision claim11(const Sets& sets, const RuleSet& r) {
  const Needed n = need(sets, {"A", "B", "D", "E", "G", "H"}, 3);
  if (!n.problem.empty()) return unclear_because(n.problem);
  std::vector<Part> parts;
  // each algorithm's parameter-specific set, then its d_lost set
  for (int a = 0; a < 3; ++a) {
    const Importance specific = importance(*n.sets[2 * a], r.importance_of_overhead);
    const Importance lost = importance(*n.sets[2 * a + 1], r.importance_of_overhead);
    Test s{Support::kUnclear, in_widths(kMuchLess * specific.bounds.lo - lost.bounds.hi,
                                        width(lost.bounds) + kMuchLess * width(specific.bounds))};
    if (lost.bounds.hi < kMuchLess * specific.bounds.lo) s.support = Support::kYes;
    if (lost.bounds.lo >= kMuchLess * specific.bounds.hi) s.support = Support::kNo;
    // the figures: d_lost's importance against half the algorithm's own parameter's
    parts.push_back(part(s,
                         n.sets[2 * a]->algorithm + ": " + lost.text + "; importance " +
                             num(lost.point) + " " + interval_text(lost.bounds) + " vs " +
                             specific.text + "; importance " + num(specific.point) + " " +
                             interval_text(specific.bounds) + "; needs < " + num(kMuchLess) +
                             " x",
                         figures(lost.point, lost.bounds, kMuchLess * specific.point)));
  }
  return decide(parts);
}

struct ClaimDef {
  int id;
  const char* text;
  Decision (*decide)(const Sets&, const RuleSet&);
};

constexpr ClaimDef kClaims[] = {
    {1, "Surge-spiral: virtually all runs of D, E, F succeed.", claim1},
    {2,
     "Casting (A): small beta gives low overhead but low success; only beta > 20 deg gives "
     "acceptable success.",
     claim2},
    {3, "Casting (B): success drops at one end of the d_lost range, overhead worsens at the other.",
     claim3},
    {4,
     "Casting (C): sigma_a barely matters until it is too high; then casting fails almost "
     "always.",
     claim4},
    {5, "Surge-spiral (D): a smaller d_gap gives lower overhead.", claim5},
    {6, "Surge-spiral (E): higher d_lost gives slightly lower overhead.", claim6},
    {7, "Surge-spiral (F): sigma_a raises the overhead, not the failure rate.", claim7},
    {8,
     "Surge-cast (G): overhead grows about linearly with d_cast, at a low rate; very small d_cast "
     "fails.",
     claim8},
    {9, "Surge-cast (I): sigma_a mainly lowers the success rate.", claim9},
    {10,
     "At the fixed values, casting is worst in both success and overhead; surge-cast is "
     "comparable to surge-spiral.",
     claim10},
    {11, "d_lost matters much less than beta, d_gap or d_cast.", claim11},
};

}  // namespace

std::string_view verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kHolds:
      return "holds";
    case Verdict::kDoesNotHold:
      return "does not hold";
    case Verdict::kUnclear:
      return "unclear";
  }
  return "unclear";
}

std::string_view rules_name(ClaimRules rules) {
  return rules == ClaimRules::kRules030 ? "0.3.0" : "0.4";
}

std::vector<ClaimResult> evaluate_claims(const std::map<std::string, SetStats>& sets,
                                         ClaimRules rules) {
  std::vector<ClaimResult> out;
  const RuleSet& r = rule_set(rules);
  for (const ClaimDef& c : kClaims) {
    const Decision d = c.decide(sets, r);
    std::vector<ClaimPart> parts;
    for (const Part& p : d.parts) {
      parts.push_back({p.text, verdict_of(p.support), p.margin, p.figures.estimate,
                       p.figures.interval.lo, p.figures.interval.hi, p.figures.threshold});
    }
    out.push_back({c.id, c.text, verdict_of(d.support), d.evidence, parts, d.margin});
  }
  return out;
}

}  // namespace plumetrace
