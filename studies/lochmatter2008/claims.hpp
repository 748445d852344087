#pragma once

#include <cmath>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/experiment/evidence.hpp"

namespace plumetrace {

/// Whether the data support a claim beyond their statistical noise (rules in docs/claims.md).
enum class Verdict { kHolds, kDoesNotHold, kUnclear };

/// Name of a verdict: "holds", "does not hold", "unclear".
std::string_view verdict_name(Verdict v);

/// The rule sets of docs/claims.md: rules 0.3.0 as first written, and rules 0.4 ("Rules 0.4:
/// rules that converge": one threshold m = 0 per directional part, claim 11 on overhead alone).
enum class ClaimRules { kRules030, kRules04 };

/// The rules the report's verdicts use; rules 0.3.0 are computed beside them.
inline constexpr ClaimRules kDefaultRules = ClaimRules::kRules04;

/// Name of a rule set: "0.3.0", "0.4".
std::string_view rules_name(ClaimRules rules);

/// One tested part of a claim, with its signed margin (docs/claims.md, "Margins").
struct ClaimPart {
  /// The part's figures, ending in "-> yes", "-> no" or "-> unclear".
  std::string text;
  /// kHolds (yes), kDoesNotHold (no) or kUnclear.
  Verdict support = Verdict::kUnclear;
  /// How far the interval lies on the claimed side of the part's threshold, in units of the
  /// interval's width: positive exactly when the part is supported; NaN when the interval
  /// cannot be computed.
  double margin = NAN;
  /// The tested quantity's point estimate, its 95% interval and the threshold it was held
  /// against (docs/claims.md, "Every verdict carries its effect and interval"); NaN where the
  /// part's test has no such number.
  double estimate = NAN;
  double lo = NAN;         ///< lower end of the interval
  double hi = NAN;         ///< upper end of the interval
  double threshold = NAN;  ///< m, M or L
};

/// The verdict on one claim of docs/claims.md, with the figures that decided it.
struct ClaimResult {
  int id = 0;                           ///< claim number, 1-11
  std::string text;                     ///< the claim as docs/claims.md words it
  Verdict verdict = Verdict::kUnclear;  ///< holds, does not hold or unclear
  std::string evidence;                 ///< the deciding figures, one clause per tested part
  std::vector<ClaimPart> parts;         ///< the tested parts, in evidence order
  /// The claim's margin: the smallest of its parts' (a conjunction holds when every part does);
  /// for claim 3, the larger of its two patterns' margins. NaN when a part's margin is NaN.
  double margin = NAN;
};

/// Evaluates the claims 1-11 of docs/claims.md from the nine sets, keyed by name "A".."I", under
/// a rule set. A claim whose sets are missing (or malformed) is kUnclear with evidence saying so.
std::vector<ClaimResult> evaluate_claims(const std::map<std::string, SetStats>& sets,
                                         ClaimRules rules = kDefaultRules);

}  // namespace plumetrace
