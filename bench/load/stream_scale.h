// Streams at scale: N StreamClip streams at `fps` opened from this one
// process, each frame's arrival time recorded, then the inter-frame interval
// judged over a window in which every stream is playing.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "latency.h"

namespace armature_load {

struct StreamScaleOptions {
  int streams = 100;
  double fps = 60;
  double seconds = 5;         // measured window (after the warm-up)
  double warmup_seconds = 1;  // after the last stream's first frame
  double late_ms = 5;         // a frame later than its due time by more is late
  std::string clip = "load_cmu";
  int server_pid = 0;  // its CPU is read from /proc/<pid>/stat; 0 = not reported
};

struct StreamScaleOutcome {
  int streams_opened = 0;  // streams that delivered a first frame
  int streams_failed = 0;  // ended with an error status
  std::string first_error;
  double open_seconds = 0;      // from the first request to the last stream's first frame
  int64_t frames = 0;           // received in the window
  int64_t frames_expected = 0;  // due in the window: window × fps × streams
  int64_t frames_lost = 0;      // index gaps (a frame never sent) over the whole run
  int64_t frames_late = 0;      // in the window, later than due + late_ms
  double max_late_ms = 0;
  Percentiles interval_ms;   // inter-frame arrival interval, all streams
  Percentiles deviation_ms;  // |interval − 1/fps|
  double worst_stream_p99_deviation_ms = 0;
  // How late the server wrote frames by its own clock (PoseFrame.wall_time −
  // index/fps): beside the arrival figures, it tells a server that falls
  // behind from a transport or client that does.
  Percentiles server_late_ms;
  double window_seconds = 0;
  double server_cpu_percent = -1;  // of one core, over the window
  double client_cpu_percent = -1;
};

StreamScaleOutcome RunStreamScale(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                                  const StreamScaleOptions& options);

}  // namespace armature_load
