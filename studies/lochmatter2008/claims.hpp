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

/// Evaluates the claims 1-11 of docs/claims.md from the nine sets, keyed by name "A".."I". A claim
/// whose sets are missing (or malformed) is kUnclear with evidence saying so.
std::vector<ClaimResult> evaluate_claims(const std::map<std::string, SetStats>& sets);

}  // namespace plumetrace
