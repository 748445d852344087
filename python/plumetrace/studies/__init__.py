"""The studies plumetrace re-runs, one subpackage each, with what their reports say."""
