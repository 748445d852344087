#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "plumetrace/io/trace_io.hpp"

namespace plumetrace {

/// How much of a trace the viewer keeps. What the eye sees is kept whatever the limits: the
/// trajectory to within `path_tolerance`, every change of controller state, every odor onset and
/// every wind sample; only the robot's animation frames and the filament snapshots are thinned.
struct ViewerOptions {
  /// Most robot frames kept for the animation (every k-th step, plus each change of state).
  std::size_t max_frames = 12000;
  /// Most filament snapshots kept (evenly thinned).
  std::size_t max_snapshots = 600;
  /// Trajectory vertices within this distance of the simplified path are dropped (m).
  double path_tolerance = 0.001;
  /// Odor detections closer than this to the previous one kept are dropped (m); onsets stay.
  double detection_spacing = 0.03;
  /// Time of the filament snapshot in the static figure (s); negative: the end of the run.
  double figure_time = -1.0;
};

/// Checks a viewer path before a run: a `.html` or `.svg` name (ConfigError naming `option`
/// otherwise) that can be created (IoError naming the file otherwise).
void check_view_path(const std::string& path, const std::string& option);

/// Writes the run as one self-contained HTML page that animates it (`.html`), or as a static
/// figure of the whole run (`.svg`); throws IoError naming the file.
void write_view(const std::string& path, const RecordedRun& run, const ViewerOptions& options);

/// The animated viewer page for a run (HTML, no external resources).
std::string viewer_html(const RecordedRun& run, const ViewerOptions& options);

/// The static figure of a whole run (SVG): the same layers as the viewer at its last frame.
std::string figure_svg(const RecordedRun& run, const ViewerOptions& options);

}  // namespace plumetrace
