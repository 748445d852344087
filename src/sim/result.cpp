#include "plumetrace/sim/result.hpp"

namespace plumetrace {

std::string_view outcome_name(Outcome outcome) {
  switch (outcome) {
    case Outcome::kRunning:
      return "running";
    case Outcome::kSuccess:
      return "success";
    case Outcome::kWall:
      return "wall";
    case Outcome::kTimeout:
      return "timeout";
    case Outcome::kGaveUp:
      return "gave_up";
  }
  return "";
}

}  // namespace plumetrace
