// A policy served by openpi policy servers (policy-interfaces.md §A1): at the 20 Hz policy rate,
// each acting env whose action queue is empty sends its observation and queues the first
// replan_steps rows of the action chunk the server answers. Requests go out one at a time in env
// order (openpi servers do not batch), so a deterministic server gives the same actions whatever
// the thread count.
//
// The request is laid out by ObservationKeys (observation_keys.h: the `tavis` preset sends the
// reference's LeRobot names, "observation.images.<camera>", "observation.state", "prompt"). The
// reply's "actions" must be H x 19 (the canonical action), float32 or float64. A reply that is
// not (wrong shape, dtype or no "actions") ends only that env's episode, as invalid_action naming
// the fault; a non-finite or absurd action does too (the step's own check). A server that fails
// (its traceback), dies or does not answer stops the run.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/policy.h"
#include "batch/remote/msgpack_value.h"
#include "batch/remote/observation_keys.h"
#include "batch/remote/openpi_session.h"

namespace tavis::remote {

struct RemotePolicyOptions {
  std::vector<std::string> servers;  // ws://HOST:PORT; env slot i talks to servers[i % size]
  // Chunk rows an env steps with before it asks again. 0 takes the whole chunk, as openpi's
  // ActionChunkBroker does; its LIBERO example re-plans every 5.
  int replan_steps = 0;
  ObservationKeys keys;  // the request's layout (LoadObservationKeys)
  batch::CameraProtocol protocol = batch::CameraProtocol::kHead;  // which of head/fixed is sent
  std::chrono::milliseconds ready_timeout{60'000};  // per server, for /healthz to answer
  std::chrono::milliseconds reply_timeout{300'000};
  std::uint64_t max_reply_bytes = kDefaultMaxReplyBytes;  // OpenpiSessionOptions::max_reply_bytes
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
  std::vector<std::string> cameras() const override { return options_.keys.PolicyCameras(); }
  // Clears the started envs' queues and answers the servers' pings (resets can take long).
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override;
  // Throws std::runtime_error naming the server, env slot and episode when a server fails. A
  // reply whose actions are not H x 19 floats becomes a fault of that env (TakeFaults).
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override;
  void TakeFaults(std::vector<batch::PolicyFault>& faults) override;

  // The requests so far, with the reconnects of every session.
  RequestTimings timings() const;
  // Each server's metadata message, in the order of options.servers.
  std::vector<Value> server_metadata() const;

 private:
  OpenpiSession& SessionOf(int env) { return *sessions_[static_cast<std::size_t>(env) % sessions_.size()]; }
  const std::string& ServerOf(int env) const { return options_.servers[static_cast<std::size_t>(env) % sessions_.size()]; }
  // Asks env's server and fills env's queue from the reply; false (and a fault) for a malformed reply.
  bool Query(const batch::Observation& observation, int env);

  RemotePolicyOptions options_;
  std::vector<std::unique_ptr<OpenpiSession>> sessions_;
  std::vector<std::deque<kinematics::Action>> queues_;  // (num_envs)
  std::vector<batch::PolicyFault> faults_;              // of the current Act
  RequestTimings timings_;
};

}  // namespace tavis::remote
