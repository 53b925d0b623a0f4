// Crowds at scale: S CrowdService.CrowdSession calls of C characters each
// (CMU-style mixed offsets and speeds on one clip) opened from this one
// process, each frame's arrival and the server's tick figures recorded, then
// judged over a window in which every crowd is ticking (issue 31).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "latency.h"

namespace armature_load {

struct CrowdScaleOptions {
  int sessions = 1;
  int characters = 1000;  // per session
  double fps = 30;
  double budget_ms = 0;       // 0 = the server's --crowd-budget-ms
  double share_quantum = 0;   // CrowdStart.share_quantum: 0 = the server's 1/120 s, < 0 = no sharing
  double seconds = 5;         // measured window (after the warm-up)
  double warmup_seconds = 1;  // after the last crowd's first frame
  std::string clip = "load_cmu";
  int server_pid = 0;  // its CPU is read from /proc/<pid>/stat; 0 = not reported
};

struct CrowdScaleOutcome {
  int sessions_opened = 0;  // crowds that delivered a first frame
  int sessions_failed = 0;  // ended with an error status or a refused character
  std::string first_error;
  double open_seconds = 0;  // from the first call to the last crowd's first frame
  double window_seconds = 0;
  int64_t frames = 0;                    // received in the window, all crowds
  int64_t frames_expected = 0;           // window × fps × sessions
  int64_t late_ticks = 0;                // in the window, the server's CrowdTickStats.late
  Percentiles interval_ms;               // inter-frame arrival interval, all crowds
  Percentiles server_interval_ms;        // the same from the server's wall_time: its own pacing
  double deferred_per_tick = 0;          // characters not updated in a tick, summed over the crowds, mean over ticks
  double updated_per_tick = 0;           // poses sent a tick, summed over the crowds
  double wire_bytes_per_joint = 0;       // frames' serialized bytes / (poses × joints)
  double server_cpu_percent = -1;        // of one core, over the window
  double server_cpu_us_per_update = -1;  // server CPU / poses sent in the window
  double server_cpu_us_per_character_tick = -1;  // server CPU / (characters × ticks) in the window
  double client_cpu_percent = -1;
};

CrowdScaleOutcome RunCrowdScale(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                                const CrowdScaleOptions& options);

}  // namespace armature_load
