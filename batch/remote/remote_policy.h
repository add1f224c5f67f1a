// A policy served by openpi policy servers (policy-interfaces.md §A1): at the 20 Hz policy rate,
// each acting env whose action queue is empty asks for a chunk and queues its first replan_steps
// rows. Three ways to ask (ServingMode), with the same records whenever the server's answer
// depends only on the request:
//   serial   one connection per server; requests one at a time in env order (a stock openpi
//            server, which neither batches nor keeps per-env state, sees exactly its protocol);
//   per-env  one connection per env slot (slot i to server i mod K), so a server can keep state
//            per connection as openpi's does; the requests of all envs due at a tick are in
//            flight together;
//   batched  one message per server per policy tick with the observations of every env due
//            there stacked on a leading axis, answered with one chunk per env (N x H x 19), so a
//            server runs one forward pass; only to servers whose metadata declares
//            batched_requests: true.
// Every request carries env_index, episode_index, step and is_first (observation_contract.h).
//
// The request is laid out by ObservationKeys (observation_keys.h: the default `tavis` preset is
// the observation contract, the dataset's keys). A reply whose "actions" is not a float32/float64
// chunk of 19-wide rows (wrong shape, dtype, or no "actions") ends only the episodes it answers,
// as invalid_action naming the fault; a non-finite or absurd action does too (the step's own
// check). A server that fails (its traceback), dies or does not answer stops the run.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/policy.h"
#include "batch/policy_kinds.h"
#include "batch/remote/msgpack_value.h"
#include "batch/remote/observation_keys.h"
#include "batch/remote/openpi_reply.h"
#include "batch/remote/openpi_session.h"

namespace tavis::batch::remote {

enum class ServingMode { kSerial, kPerEnv, kBatched };

// "serial", "per-env", "batched"; ParseServingMode throws std::invalid_argument naming other text.
const char* ToString(ServingMode mode);
ServingMode ParseServingMode(const std::string& text);

struct RemotePolicyOptions {
  std::vector<std::string> servers;  // ws://HOST:PORT; env slot i talks to servers[i % size]
  // Chunk rows an env steps with before it asks again. 0 takes the whole chunk, as openpi's
  // ActionChunkBroker does; its LIBERO example re-plans every 5.
  int replan_steps = 0;
  ServingMode mode = ServingMode::kSerial;
  ObservationKeys keys;                                           // the request's layout (LoadObservationKeys)
  batch::CameraProtocol protocol = batch::CameraProtocol::kHead;  // which of head/fixed is sent
  std::chrono::milliseconds ready_timeout{60'000};                // per server, for /healthz to answer
  std::chrono::milliseconds reply_timeout{300'000};
  std::uint64_t max_reply_bytes = kDefaultMaxReplyBytes;  // OpenpiSessionOptions::max_reply_bytes
  // The robot's observation.state length, checked against a server's declared contract (0: not checked).
  int state_size = 0;
  // The cell's task and robot, checked against those a server's contract says its policy was
  // trained for ("": not checked).
  std::string task;
  std::string robot;
};

// Waits for `server` as RemotePolicy does, connects, and returns the metadata map it sends first
// (the connection is then closed): how a command reads a server's declared contract
// (server_contract.h) before it plans a cell. Throws std::runtime_error naming the server when it
// does not become ready or cannot be reached.
Value ReadServerMetadata(const std::string& server, const RemotePolicyOptions& options);

// What the requests of a run took, one entry per request message, in request order.
struct RequestTimings {
  std::vector<double> round_trip_ms;    // request sent to reply read, measured here
  std::vector<double> server_infer_ms;  // server_timing.infer_ms, for the replies that carry it
  std::vector<int> envs_per_request;    // envs a message asked for (1 unless batched)
  int policy_ticks = 0;                 // ticks at which at least one env asked
  double wait_ms = 0.0;                 // wall time Act spent waiting for replies
  int reconnects = 0;
};

class RemotePolicy : public batch::Policy {
 public:
  // Waits for every server (ready_timeout each: its /healthz answering 200, or, for a server that
  // has no /healthz, its websocket accepting), then connects and reads its metadata (per-env: one
  // connection per env slot). Throws std::invalid_argument for no server, a malformed URL,
  // negative replan_steps, or batched mode with a server whose metadata does not declare
  // batched_requests, or a server whose declared contract (server_contract.h) is malformed or
  // contradicts the layout, the state size, replan_steps, the task or the robot (naming both
  // values), and std::runtime_error naming the server when it does not become ready or cannot be reached.
  RemotePolicy(RemotePolicyOptions options, int num_envs);

  std::string name() const override { return batch::PolicyName(batch::PolicyKind::kOpenpi); }
  int control_ticks_per_action() const override { return 3; }
  std::vector<std::string> cameras() const override { return options_.keys.PolicyCameras(); }
  // Clears the started envs' queues and answers the servers' pings (resets can take long).
  void Reset(const batch::Observation& observation, const std::vector<uint8_t>& started) override;
  // Throws std::runtime_error naming the server, env slot and episode when a server fails. A
  // reply whose actions are not H x 19 floats (N x H x 19 batched) becomes a fault of the envs it
  // answers (TakeFaults).
  void Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
           batch::ActionBatch& actions) override;
  void TakeFaults(std::vector<batch::PolicyFault>& faults) override;

  // The requests so far, with the reconnects of every session.
  RequestTimings timings() const;
  // Each server's metadata message, in the order of options.servers.
  std::vector<Value> server_metadata() const;

 private:
  // One message in flight: the envs it asks for (ascending) and the session it goes to.
  struct Exchange {
    std::vector<int> envs;
    OpenpiSession* session = nullptr;
    const std::string* server = nullptr;
    Value request;
    InferResult result;
    std::exception_ptr error;
  };

  int ServerIndexOf(int env) const { return env % static_cast<int>(options_.servers.size()); }
  // The session env's requests go to: its own (per-env) or its server's.
  OpenpiSession& SessionOf(int env);
  // The messages for the envs that need a chunk now, by mode.
  std::vector<Exchange> PlanExchanges(const batch::Observation& observation, const std::vector<int>& due);
  // Sends every exchange and waits for its reply: one after the other (serial), or all at once.
  void RunExchanges(std::vector<Exchange>& exchanges) const;
  // Fills the queues of the exchange's envs from its reply; a malformed reply faults them all.
  void TakeReply(const batch::Observation& observation, Exchange& exchange);
  void QueueRows(int env, const ActionChunk& chunk);

  RemotePolicyOptions options_;
  // serial and batched: one per server; per-env: one per env slot.
  std::vector<std::unique_ptr<OpenpiSession>> sessions_;
  std::vector<std::deque<kinematics::Action>> queues_;  // (num_envs)
  std::vector<batch::PolicyFault> faults_;              // of the current Act
  RequestTimings timings_;
};

}  // namespace tavis::batch::remote
