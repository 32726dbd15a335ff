// A job as the scheduler keeps it: its record (protocol/job_json.h: what
// the store keeps and clients read) and what only a running server knows.
#pragma once

#include <chrono>

#include "job_json.h"

namespace cgview::server {

using protocol::active;
using protocol::job_json;
using protocol::job_state_from;
using protocol::JobState;
using protocol::progress_event;
using protocol::to_string;

struct Job : protocol::JobRecord {
  bool cancelled = false;  // asked to stop: its state is already cancelled, its worker may still run
  bool in_flight = false;  // handed to its executor: a worker may still write into its directory
  bool deleted = false;    // deleted while its cancelled worker still ran: gone for everyone, forgotten when it ends
  std::chrono::steady_clock::time_point last_event;
  std::chrono::steady_clock::time_point run_from;  // its worker's start, for run_s
  // A shorter time limit than the server's, set by the server's own
  // submissions (a graded run); 0: the server's.  Not stored: a job queued
  // again after a restart runs under the server's.
  double timeout_s = 0;
};

}  // namespace cgview::server
