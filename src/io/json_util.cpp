#include "plumetrace/io/json_util.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "plumetrace/core/files.hpp"

namespace plumetrace::detail {

json value_to_json(const ConfigValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json result_json(const RunResult& r, const RunInfo& info) {
  json out{{"algorithm", info.algorithm}};
  RunResult::fields(r, [&](const ResultField& f, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    json& cell = out[std::string(f.name)];
    if constexpr (std::is_same_v<T, Outcome>) {
      cell = std::string(outcome_name(value));
    } else if constexpr (std::is_floating_point_v<T>) {
      cell = f.nullable ? number_or_null(value) : json(value);
    } else {
      cell = value;
    }
  });
  out["seed"] = info.seed;
  out["trial"] = info.trial;
  out["agent"] = info.agent;
  out["version"] = std::string(version());
  return out;
}

namespace {

// lengths (m) to 0.1 mm, enough for a figure and far below a step of the robot
json lengths_json(const std::vector<double>& v) {
  json out = json::array();
  for (const double x : v) out.push_back(std::round(x * 1e4) / 1e4);
  return out;
}

// a pooled gap analysis (docs/plume-statistics.md)
json gap_stats_json(const GapStats& g) {
  return {{"paths", g.paths},
          {"paths_with_odor", g.paths_with_odor},
          {"samples", g.samples},
          {"detections", g.detections},
          {"detected_fraction",
           g.samples > 0 ? json(static_cast<double>(g.detections) / static_cast<double>(g.samples))
                         : json(nullptr)},
          {"gaps", g.gaps.size()},
          {"median", number_or_null(g.median)},
          {"p90", number_or_null(g.p90)},
          {"longest", number_or_null(g.longest)},
          {"longer_than_d_lost", g.longer_than_d_lost},
          {"fraction_longer", number_or_null(g.fraction_longer)},
          {"lengths", lengths_json(g.gaps)}};
}

// count / of, or null when of is 0
json share(long count, long of) {
  return of > 0 ? json(static_cast<double>(count) / static_cast<double>(of)) : json(nullptr);
}

}  // namespace

json plume_stats_json(const PlumeStats& st) {
  json along = json::array(), across = json::array();
  for (const auto& a : st.along) {
    json j = gap_stats_json(a.gaps);
    j["offset"] = a.offset;
    j["leading_median"] = number_or_null(a.leading_median);
    along.push_back(j);
  }
  for (const auto& c : st.across) {
    json j = gap_stats_json(c.gaps);
    j["distance"] = c.distance;
    j["band_median"] = number_or_null(c.band_median);
    j["band_max"] = number_or_null(c.band_max);
    j["band_widths"] = lengths_json(c.band_widths);
    across.push_back(j);
  }
  const auto& r = st.release;
  const auto& s = st.spirals;
  return {{"trials", st.trials},
          {"seed", st.seed},
          {"d_lost", st.d_lost},
          {"speed", st.speed},
          {"turns", st.turns},
          {"along", along},
          {"across", across},
          {"release",
           {{"trials", r.trials},
            {"in_odor", r.in_odor},
            {"within_d_lost", r.within_d_lost},
            {"fraction_in_odor", share(r.in_odor, r.trials)},
            {"fraction_within_d_lost", share(r.within_d_lost, r.trials)}}},
          {"spirals",
           {{"surges", s.surges},
            {"lost", s.lost},
            {"within_one_turn", s.within_one_turn},
            {"reacquired", s.reacquired},
            {"walls", s.walls},
            {"out_of_turns", s.out_of_turns},
            {"fraction_one_turn", share(s.within_one_turn, s.lost)},
            {"fraction_reacquired", share(s.reacquired, s.lost)},
            {"distance_median", number_or_null(s.distance_median)},
            {"distances", lengths_json(s.distances)},
            {"turns_to_odor", lengths_json(s.turns_to_odor)},
            {"loss_x", lengths_json(s.loss_x)}}}};
}

json team_stats_json(const TeamStats& t) {
  return {{"teams", t.teams},
          {"robots", t.robots},
          {"successes", t.successes},
          {"success_rate", number_or_null(t.success_rate)},
          {"success_lo", number_or_null(t.success_ci.lo)},
          {"success_hi", number_or_null(t.success_ci.hi)},
          {"mean_first_arrival", number_or_null(t.mean_first_arrival)},
          {"mean_arrivals", number_or_null(t.mean_arrivals)},
          {"mean_d_t_sum", number_or_null(t.mean_d_t_sum)}};
}

json stats_json(const PointStats& p) {
  return {{"runs", p.runs},
          {"successes", p.successes},
          {"walls", p.walls},
          {"timeouts", p.timeouts},
          {"gave_up", p.gave_up},
          {"wrong_declarations", p.wrong_declarations},
          {"success_rate", number_or_null(p.success_rate)},
          {"success_lo", number_or_null(p.success_ci.lo)},
          {"success_hi", number_or_null(p.success_ci.hi)},
          {"overhead",
           {{"n", p.overhead.n},
            {"mean", number_or_null(p.overhead.mean)},
            // why: the interval printed everywhere, the bootstrap (issue 22); boot_lo and boot_hi
            // repeat it for readers of files of 0.3.0, whose lo and hi were t intervals
            {"lo", number_or_null(p.overhead_bootstrap.lo)},
            {"hi", number_or_null(p.overhead_bootstrap.hi)},
            {"boot_lo", number_or_null(p.overhead_bootstrap.lo)},
            {"boot_hi", number_or_null(p.overhead_bootstrap.hi)},
            {"median", number_or_null(p.overhead_quartiles.median)},
            {"q1", number_or_null(p.overhead_quartiles.q1)},
            {"q3", number_or_null(p.overhead_quartiles.q3)}}},
          {"mean_time", number_or_null(p.mean_time)},
          {"mean_losses", number_or_null(p.mean_losses)}};
}

std::string csv_text(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + '"';
}

namespace {

constexpr char kBase64Digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

}  // namespace

std::string base64(const std::vector<std::uint8_t>& bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b0 = bytes[i];
    const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
    const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const std::uint32_t v = (b0 << 16) | (b1 << 8) | b2;
    out += kBase64Digits[(v >> 18) & 63];
    out += kBase64Digits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kBase64Digits[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kBase64Digits[v & 63] : '=';
  }
  return out;
}

bool unbase64(std::string_view text, std::vector<std::uint8_t>& bytes) {
  bytes.clear();
  if (text.size() % 4 != 0) return false;
  bytes.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    std::uint32_t v = 0;
    int pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      std::uint32_t digit = 0;
      if (c == '=' && i + 4 == text.size() && k >= 2) {
        ++pad;
      } else {
        const char* at = std::find(kBase64Digits, kBase64Digits + 64, c);
        // why: a digit after padding, or one outside the alphabet, is not base64
        if (at == kBase64Digits + 64 || pad > 0) return false;
        digit = static_cast<std::uint32_t>(at - kBase64Digits);
      }
      v = (v << 6) | digit;
    }
    bytes.push_back(static_cast<std::uint8_t>(v >> 16));
    if (pad < 2) bytes.push_back(static_cast<std::uint8_t>((v >> 8) & 0xff));
    if (pad < 1) bytes.push_back(static_cast<std::uint8_t>(v & 0xff));
  }
  return true;
}

Quantizer Quantizer::over(double lo, double hi, double finest) {
  if (!(lo <= hi)) return {0.0, std::max(finest, 1.0)};
  const double unit = std::max(finest, (hi - lo) / 65535.0);
  return {lo, unit > 0.0 ? unit : 1.0};
}

std::uint16_t Quantizer::operator()(double v) const {
  if (std::isnan(v)) return 0;
  return static_cast<std::uint16_t>(std::clamp(std::round((v - origin) / unit), 0.0, 65535.0));
}

std::string quantized_base64(const Quantizer& q, const std::vector<double>& values) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(2 * values.size());
  for (const double v : values) {
    const std::uint16_t word = q(v);
    bytes.push_back(static_cast<std::uint8_t>(word & 0xff));
    bytes.push_back(static_cast<std::uint8_t>(word >> 8));
  }
  return base64(bytes);
}

}  // namespace plumetrace::detail
