#include "plumetrace/experiment/evidence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace plumetrace::evidence {

// the outcome of a test

std::string_view support_name(Support s) {
  return s == Support::kYes ? "yes" : s == Support::kNo ? "no" : "unclear";
}

Part part(const Test& test, const std::string& text, const Figures& figures) {
  const Support s = test.support;
  std::string out = text;
  out.append(" -> ").append(support_name(s));
  return {s, test.margin, std::move(out), figures};
}

// the tests

// why: a floor on the width keeps a zero-width interval (a single degenerate value) from giving
// an infinite margin
double in_widths(double distance, double width) {
  constexpr double kMinWidth = 1e-6;
  if (std::isnan(distance) || std::isnan(width)) return NAN;
  return distance / std::max(width, kMinWidth);
}

double width(const Interval& i) { return i.hi - i.lo; }

std::string_view directional_rule_name(DirectionalRule rule) {
  return rule == DirectionalRule::kSingleThreshold ? "single-threshold" : "legacy-0.3.0";
}

Test directional(const Interval& effect, double m, DirectionalRule rule) {
  const double yes_above = rule == DirectionalRule::kSingleThreshold ? m : 0.0;
  Test t{Support::kUnclear, in_widths(effect.lo - yes_above, width(effect))};
  if (effect.lo > yes_above)
    t.support = Support::kYes;
  else if (effect.hi < m)
    t.support = Support::kNo;
  return t;
}

Test within(const Interval& effect, double margin) {
  Test t{Support::kUnclear,
         in_widths(std::fmin(effect.lo + margin, margin - effect.hi), width(effect))};
  if (std::isnan(effect.lo) || std::isnan(effect.hi)) t.margin = NAN;
  if (effect.lo > -margin && effect.hi < margin)
    t.support = Support::kYes;
  else if (effect.lo >= margin || effect.hi <= -margin)
    t.support = Support::kNo;
  return t;
}

Test below(const Interval& value, double limit) {
  Test t{Support::kUnclear, in_widths(limit - value.hi, width(value))};
  if (value.hi < limit)
    t.support = Support::kYes;
  else if (value.lo >= limit)
    t.support = Support::kNo;
  return t;
}

Test at_least(const Interval& value, double limit) {
  Test t{Support::kUnclear, in_widths(value.lo - limit, width(value))};
  if (value.lo >= limit)
    t.support = Support::kYes;
  else if (value.hi < limit)
    t.support = Support::kNo;
  return t;
}

double weakest(const std::vector<double>& margins) {
  double out = INFINITY;
  for (double m : margins) {
    if (std::isnan(m)) return NAN;
    out = std::fmin(out, m);
  }
  return margins.size() ? out : NAN;
}

Test all_of(const std::vector<Test>& tests) {
  bool all_yes = true;
  Test out{Support::kUnclear, INFINITY};
  for (const Test& t : tests) {
    out.margin =
        std::isnan(t.margin) || std::isnan(out.margin) ? NAN : std::fmin(out.margin, t.margin);
    if (t.support == Support::kNo) out.support = Support::kNo;
    if (t.support != Support::kYes) all_yes = false;
  }
  if (out.support != Support::kNo && all_yes) out.support = Support::kYes;
  return out;
}

Support combine(const std::vector<Part>& parts) {
  if (parts.empty()) return Support::kUnclear;
  bool all_yes = true;
  for (const Part& p : parts) {
    if (p.support == Support::kNo) return Support::kNo;
    if (p.support != Support::kYes) all_yes = false;
  }
  return all_yes ? Support::kYes : Support::kUnclear;
}

Decision decide(const std::vector<Part>& parts, const std::string& preamble) {
  std::vector<std::string> texts;
  if (!preamble.empty()) texts.push_back(preamble);
  Decision d;
  d.margin = parts.empty() ? NAN : INFINITY;
  for (const Part& p : parts) {
    texts.push_back(p.text);
    d.parts.push_back(p);
    d.margin = std::isnan(p.margin) || std::isnan(d.margin) ? NAN : std::fmin(d.margin, p.margin);
  }
  d.support = combine(parts);
  d.evidence = join(texts, "; ");
  return d;
}

Decision unclear_because(const std::string& problem) {
  Decision d;
  d.evidence = problem;
  return d;
}

// the wording of the figures

std::string num(double v) { return std::isnan(v) ? "n/a" : format("%.3f", v); }

std::string pct(double v) { return std::isnan(v) ? "n/a" : format("%+.1f%%", 100.0 * v); }

std::string margin_pct(double v) { return format("%.0f%%", 100.0 * v); }

namespace {

// why: appending instead of "[" + a + ... avoids GCC 12's false -Wrestrict (GCC bug 105329)
std::string bracket(const std::string& lo, const std::string& hi) {
  std::string out = "[";
  out.append(lo).append(", ").append(hi).append("]");
  return out;
}

}  // namespace

std::string interval_text(const Interval& i) { return bracket(num(i.lo), num(i.hi)); }

std::string pct_interval_text(const Interval& i) { return bracket(pct(i.lo), pct(i.hi)); }

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string out;
  for (const auto& p : parts) {
    if (!out.empty()) out += sep;
    out += p;
  }
  return out;
}

std::string value_text(double v) { return format("%g", v); }

// rates, means and their differences

Interval negate(const Interval& i) { return {-i.hi, -i.lo}; }

Interval scaled(const Interval& i, double f) {
  if (!(f > 0.0) || !std::isfinite(f)) return {};
  return {i.lo * f, i.hi * f};
}

std::string describe(const Rate& r) {
  return format("%lld/%lld = ", static_cast<long long>(r.k), static_cast<long long>(r.n)) +
         num(r.p()) + " " + interval_text(r.ci());
}

std::string describe(const MeanCi& m) {
  if (m.n == 0) return "no successful run";
  if (m.n == 1) return num(m.mean) + " (n=1)";
  return num(m.mean) + " " + interval_text({m.lo, m.hi}) +
         format(" (n=%lld)", static_cast<long long>(m.n));
}

Interval rate_difference(const Rate& a, const Rate& b) {
  return newcombe_difference(a.k, a.n, b.k, b.n);
}

Interval relative_difference(const MeanCi& a, const MeanCi& b, const MeanCi& ref) {
  return scaled(welch_difference(a, b), 1.0 / ref.mean);
}

double relative_point(const MeanCi& a, const MeanCi& b, const MeanCi& ref) {
  return (a.mean - b.mean) / ref.mean;
}

// pooled groups of points

std::string symbol(const SetStats& s) {
  std::string k = s.key;
  if (const auto dot = k.rfind('.'); dot != std::string::npos) k = k.substr(dot + 1);
  if (k.size() > 4 && k.ends_with("_deg")) k.resize(k.size() - 4);
  return k.empty() ? "value" : k;
}

int size_of(const SetStats& s) { return static_cast<int>(s.values.size()); }

std::vector<int> indices(int first, int end) {
  std::vector<int> out;
  for (int i = first; i < end; ++i) out.push_back(i);
  return out;
}

std::vector<int> lower_half(const SetStats& s) { return indices(0, size_of(s) / 2); }

std::vector<int> upper_half(const SetStats& s) {
  return indices(size_of(s) - size_of(s) / 2, size_of(s));
}

Group pool(const SetStats& s, const std::vector<int>& idx) {
  Group g;
  std::vector<MeanCi> parts;
  for (int i : idx) {
    g.rate.k += s.points[i].successes;
    g.rate.n += s.points[i].runs;
    parts.push_back(s.points[i].overhead);
  }
  g.overhead = pooled_mean_ci(parts);
  if (!idx.empty()) {
    const std::string first = value_text(s.values[idx.front()]);
    const std::string last = value_text(s.values[idx.back()]);
    g.label = s.name + " " + symbol(s) + " " + (idx.size() == 1 ? first : first + "-" + last);
  }
  return g;
}

namespace {

bool same_double(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

bool same_runs(const PointStats& a, const PointStats& b) {
  return a.runs == b.runs && a.successes == b.successes && a.walls == b.walls &&
         a.timeouts == b.timeouts && a.gave_up == b.gave_up && a.overhead.n == b.overhead.n &&
         same_double(a.overhead.mean, b.overhead.mean) &&
         same_double(a.overhead.stddev, b.overhead.stddev) &&
         same_double(a.mean_time, b.mean_time) && same_double(a.mean_losses, b.mean_losses);
}

PooledSets pool_sets(const std::vector<const SetStats*>& sets, Points which) {
  PooledSets out;
  Group& g = out.group;
  std::vector<MeanCi> parts;
  std::vector<const PointStats*> fixed_taken;
  std::vector<std::string> names;
  for (const SetStats* s : sets) {
    for (int i = 0; i < size_of(*s); ++i) {
      const bool is_fixed = i == s->fixed_index;
      if (which == Points::kFixedOnly && !is_fixed) continue;
      const PointStats& p = s->points[i];
      if (is_fixed) {
        const bool repeat = std::any_of(fixed_taken.begin(), fixed_taken.end(),
                                        [&p](const PointStats* q) { return same_runs(p, *q); });
        if (repeat) continue;
        fixed_taken.push_back(&p);
      }
      g.rate.k += p.successes;
      g.rate.n += p.runs;
      parts.push_back(p.overhead);
    }
    names.push_back(s->name);
  }
  g.overhead = pooled_mean_ci(parts);
  g.label = join(names, "+");
  out.distinct_fixed = static_cast<int>(fixed_taken.size());
  return out;
}

std::vector<Group> thirds(const SetStats& s) {
  const int size = size_of(s);
  std::vector<Group> out;
  for (int t = 0; t < 3; ++t) out.push_back(pool(s, indices(size * t / 3, size * (t + 1) / 3)));
  return out;
}

// fits and spreads

LineFit fit_line(const SetStats& s) {
  LineFit fit;
  std::vector<int> used;
  for (int i = 0; i < size_of(s); ++i) {
    if (s.points[i].overhead.n >= 2 && std::isfinite(s.points[i].overhead.stddev)) {
      used.push_back(i);
    }
  }
  fit.points = static_cast<int>(used.size());
  if (fit.points < 3) return fit;
  double sn = 0, sx = 0, sy = 0;
  for (int i : used) {
    const double w = static_cast<double>(s.points[i].overhead.n);
    sn += w;
    sx += w * s.values[i];
    sy += w * s.points[i].overhead.mean;
  }
  const double xbar = sx / sn, ybar = sy / sn;
  double sxx = 0, sxy = 0, ss_pure = 0;
  for (int i : used) {
    const MeanCi& o = s.points[i].overhead;
    const double w = static_cast<double>(o.n);
    sxx += w * (s.values[i] - xbar) * (s.values[i] - xbar);
    sxy += w * (s.values[i] - xbar) * (o.mean - ybar);
    ss_pure += (w - 1.0) * o.stddev * o.stddev;
  }
  fit.n = static_cast<std::int64_t>(sn);
  fit.slope = sxy / sxx;
  const double intercept = ybar - fit.slope * xbar;
  double ss_lack = 0;
  fit.max_deviation = 0;
  for (int i : used) {
    const MeanCi& o = s.points[i].overhead;
    const double dev = o.mean - (intercept + fit.slope * s.values[i]);
    ss_lack += static_cast<double>(o.n) * dev * dev;
    fit.max_deviation = std::max(fit.max_deviation, std::fabs(dev));
  }
  const double x_min = s.values[used.front()], x_max = s.values[used.back()];
  fit.level = intercept + fit.slope * x_min;
  fit.span = x_max - x_min;
  const double dof = sn - 2.0;
  const double se = std::sqrt((ss_pure + ss_lack) / dof / sxx);
  const double t = student_t_quantile(0.975, dof);
  fit.slope_ci = {fit.slope - t * se, fit.slope + t * se};
  // lack of fit: F = (SS_lack / (k - 2)) / (SS_pure / (N - k)), upper tail via I_x(d2/2, d1/2)
  const double d1 = fit.points - 2.0, d2 = sn - fit.points;
  if (d2 > 0 && ss_pure > 0) {
    const double f = (ss_lack / d1) / (ss_pure / d2);
    fit.lack_of_fit_p = regularized_beta(d2 / (d2 + d1 * f), 0.5 * d2, 0.5 * d1);
  } else if (d2 > 0) {
    fit.lack_of_fit_p = ss_lack > 0 ? 0.0 : 1.0;
  }
  fit.ok = sxx > 0 && std::isfinite(fit.slope) && fit.level > 0;
  return fit;
}

Spread spread(const std::vector<double>& values, const std::vector<Interval>& intervals) {
  Spread out;
  if (values.size() < 2) return out;
  double v_max = -INFINITY, v_min = INFINITY, lo_max = -INFINITY, lo_min = INFINITY;
  double hi_max = -INFINITY, hi_min = INFINITY;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(intervals[i].lo) || !std::isfinite(intervals[i].hi)) return out;
    v_max = std::max(v_max, values[i]);
    v_min = std::min(v_min, values[i]);
    lo_max = std::max(lo_max, intervals[i].lo);
    lo_min = std::min(lo_min, intervals[i].lo);
    hi_max = std::max(hi_max, intervals[i].hi);
    hi_min = std::min(hi_min, intervals[i].hi);
  }
  out.point = v_max - v_min;
  out.bounds = {std::max(0.0, lo_max - hi_min), hi_max - lo_min};
  return out;
}

}  // namespace plumetrace::evidence
