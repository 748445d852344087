#include "plumetrace/io/exports.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"

namespace plumetrace {

namespace {

std::string interval_text(double value, double lo, double hi, int digits) {
  if (!std::isfinite(value)) return "n/a";
  char buf[96];
  if (std::isfinite(lo) && std::isfinite(hi)) {
    std::snprintf(buf, sizeof buf, "%.*f [%.*f, %.*f]", digits, value, digits, lo, digits, hi);
  } else {
    std::snprintf(buf, sizeof buf, "%.*f", digits, value);
  }
  return buf;
}

std::string values_text(const ExpandedSweep& sweep, const SweepPoint& p) {
  std::string out;
  for (std::size_t a = 0; a < p.values.size(); ++a) {
    const auto& v = p.values[a];
    out += (a ? ", " : "") + sweep.def.axes[a].key + "=" +
           (std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : format_value(v));
  }
  return out;
}

}  // namespace

std::string summary_table(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                          int runs_override) {
  // the cells first, then each column as wide as its widest cell (issue 22: long point texts
  // pushed their rows out of line)
  std::vector<std::array<std::string, 5>> cells{
      {"sweep", "point", "runs", "success [Wilson 95%]", "overhead [bootstrap 95%]"}};
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    for (const auto& p : sweep.points) {
      const PointStats st = summarize(point_runs(rows, sweep.def.name, p.index, runs));
      // why: the overhead d_t/d_u is at least 1; the percentile bootstrap lies within the
      // sample, where a t interval of a few runs reached below 0 (issue 22)
      cells.push_back(
          {sweep.def.name, values_text(sweep, p), std::to_string(st.runs),
           interval_text(st.success_rate, st.success_ci.lo, st.success_ci.hi, 2),
           interval_text(st.overhead.mean, st.overhead_bootstrap.lo, st.overhead_bootstrap.hi, 3)});
    }
  }
  // characters, not bytes: a UTF-8 continuation byte starts no character
  const auto width = [](const std::string& text) {
    return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
      return (static_cast<unsigned char>(c) & 0xc0) != 0x80;
    }));
  };
  std::array<std::size_t, 5> widths{};
  for (const auto& row : cells) {
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], width(row[c]));
  }
  std::string out;
  for (const auto& row : cells) {
    std::string text;
    for (std::size_t c = 0; c < row.size(); ++c) {
      const std::string pad(widths[c] - width(row[c]), ' ');
      // the runs right-aligned, the rest left; no spaces after the last column
      text += c == 2 ? pad + row[c] : row[c] + (c + 1 < row.size() ? pad : "");
      if (c + 1 < row.size()) text += "  ";
    }
    out += text + "\n";
  }
  return out;
}

void write_exports(const std::string& out, const std::vector<ExpandedSweep>& sweeps,
                   const std::vector<RunRow>& rows, int runs_override) {
  write_runs_csv(out + "/runs.csv", sweeps, rows);
  write_teams_csv(out + "/teams.csv", sweeps, rows);
  write_summary_csv(out + "/summary.csv", sweeps, rows, runs_override);
  write_results_json(out + "/results.json", sweeps, rows, runs_override);
}

std::vector<IncompletePoint> export_store(const std::string& store,
                                          const std::vector<ExpandedSweep>& sweeps,
                                          const std::string& out, int runs_override) {
  const auto rows = read_campaign_rows(store, sweeps);
  make_output_folder(out, "--out");
  write_exports(out, sweeps, rows, runs_override);
  return incomplete_points(sweeps, rows, runs_override);
}

}  // namespace plumetrace
