#pragma once
// What the viewer keeps of a trace (private to the library; tests include it).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/trace.hpp"

namespace plumetrace::view {

/// Indices (ascending) of the points a Douglas-Peucker simplification keeps: every dropped point
/// lies within `tolerance` (m) of the segment between the kept points around it; the first and
/// last points are always kept.
std::vector<std::size_t> simplify(const std::vector<double>& x, const std::vector<double>& y,
                                  double tolerance);

/// Steps (ascending) that are vertices of the drawn trajectory: the path simplified within
/// `tolerance`, separately for each stretch of one controller state, so that every change of
/// state is a vertex. The segment ending at a vertex is drawn in that vertex's state.
std::vector<std::size_t> path_steps(const std::vector<TraceStep>& steps, double tolerance);

/// Steps (ascending) kept as animation frames: all of them when there are at most `max_frames`,
/// else every k-th, the last, and every step whose state differs from the step before.
std::vector<std::size_t> frame_steps(const std::vector<TraceStep>& steps, std::size_t max_frames);

/// Indices of at most `max_count` of `n` items, evenly spread, first and last included.
std::vector<std::size_t> thin_evenly(std::size_t n, std::size_t max_count);

/// Steps shown as odor detections: every onset (odor after a step without), and further steps in
/// odor at least `spacing` (m) from the previous detection kept.
std::vector<std::size_t> detection_steps(const std::vector<TraceStep>& steps, double spacing);

/// The viewer page (src/viewer_page.html, compiled in) with its data placeholder.
std::string_view page_template();

/// The colours (#rrggbb) of controller states, given in order of first appearance: the report's
/// colour of each state it names, the report's extra colours in turn for the others.
std::vector<std::string> state_colors(const std::vector<std::string>& names);

/// The report's colour (#rrggbb) of an outcome.
std::string outcome_color(Outcome outcome);

/// The smallest of 1, 2 and 5 times a power of ten that is at least `at_least` (> 0): the length
/// of a scale bar or a tick step.
double nice_length(double at_least);

/// The grid of the detection region the viewer draws: square cells over the arena at the odor
/// sensor's height, 5 cm on a side (coarser on arenas over 40 m).
MapGrid detection_grid(const Scenario& scenario);

/// A mask as run lengths: cells off, then on, then off and so on, in order; the run of cells off
/// after the last cell on is left out (an empty list: none on).
std::vector<std::size_t> mask_runs(const std::vector<std::uint8_t>& mask);

}  // namespace plumetrace::view
