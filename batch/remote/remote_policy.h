// A policy served by openpi policy servers (policy-interfaces.md §A1): at the 20 Hz policy rate,
// each acting env whose action queue is empty sends its observation and queues the first
// replan_steps rows of the action chunk the server answers. Requests go out one at a time in env
// order (openpi servers do not batch), so a deterministic server gives the same actions whatever
// the thread count.
//
// The observation map uses the reference's LeRobot names (the `tavis` key layout):
//   "observation.images.<camera>"  uint8 H x W x 3, for head, left_wrist, right_wrist (under the
//                                  fixed protocol the "head" entry carries the fixed camera, so a
//                                  policy gets the same keys under both protocols)
//   "observation.state"            float32 (D), the robot's observation_state layout
//   "prompt"                       str, the episode's instruction
// The reply's "actions" must be H x 19 (the canonical action), float32 or float64.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "batch/policy.h"
#include "batch/remote/msgpack_value.h"
#include "batch/remote/openpi_session.h"

namespace tavis::remote {

struct RemotePolicyOptions {
  std::vector<std::string> servers;  // ws://HOST:PORT; env slot i talks to servers[i % size]
  // Chunk rows an env steps with before it asks again. 0 takes the whole chunk, as openpi's
  // ActionChunkBroker does; its LIBERO example re-plans every 5.
  int replan_steps = 0;
  std::chrono::milliseconds ready_timeout{60'000};  // per server, for /healthz to answer
  std::chrono::milliseconds reply_timeout{300'000};
};

// What the requests of a run took, one entry per request, in request order.
struct RequestTimings {
  std::vector<double> round_trip_ms;    // request sent to reply read, measured here
  std::vector<double> server_infer_ms;  // server_timing.infer_ms, for the replies that carry it
  int reconnects = 0;
};

class RemotePolicy : public batch::Policy {
 public:
  // Waits for every server's /healthz (ready_timeout each), then connects and reads its metadata.
  // Throws std::invalid_argument for no server, a malformed URL or negative replan_steps, and
  // std::runtime_error naming the server when it does not become ready or cannot be reached.
  RemotePolicy(RemotePolicyOptions options, int num_envs);

  std::string name() const override { return "openpi"; }
  int control_ticks_per_action() const override { return 3; }
  std::vector<std::string> cameras() const override { return {"head", "left_wrist", "right_wrist"}; }
  // Clears the started envs' queues and answers the servers' pings (resets can take long).
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override;
  // Throws std::runtime_error naming the server, env slot and episode for a server error or a
  // reply whose actions are not H x 19 floats. A non-finite value is passed on: the episode
  // driver stops the cell naming the episode and the entry.
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override;

  // The requests so far, with the reconnects of every session.
  RequestTimings timings() const;

 private:
  OpenpiSession& SessionOf(int env) { return *sessions_[static_cast<std::size_t>(env) % sessions_.size()]; }
  const std::string& ServerOf(int env) const { return options_.servers[static_cast<std::size_t>(env) % sessions_.size()]; }
  // Asks env's server and fills env's queue from the reply.
  void Query(const batch::Observation& observation, int env);

  RemotePolicyOptions options_;
  std::vector<std::unique_ptr<OpenpiSession>> sessions_;
  std::vector<std::deque<kinematics::Action>> queues_;  // (num_envs)
  RequestTimings timings_;
};

// The request for `env` in the `tavis` key layout above. Throws std::logic_error when the
// observation lacks images or proprioception (the episode driver provides both).
Value BuildTavisObservation(const batch::Observation& observation, const std::vector<std::string>& cameras, int env);

}  // namespace tavis::remote
