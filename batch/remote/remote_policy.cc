#include "batch/remote/remote_policy.h"

#include <algorithm>
#include <stdexcept>

#include "batch/remote/health_probe.h"
#include "batch/remote/openpi_reply.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/websocket_url.h"

namespace tavis::remote {
namespace {

std::string EnvContext(const batch::Observation& observation, int env, const std::string& server) {
  return "env slot " + std::to_string(env) + " (episode " + std::to_string(observation.state.episode[env]) +
         ", server " + server + ")";
}

std::unique_ptr<OpenpiSession> OpenWhenReady(const std::string& server, const RemotePolicyOptions& options) {
  const WebSocketUrl url = ParseWebSocketUrl(server);
  try {
    WaitForHealthz(url, options.ready_timeout);
    OpenpiSessionOptions session;
    session.url = server;
    session.reply_timeout = options.reply_timeout;
    session.max_reply_bytes = options.max_reply_bytes;
    return std::make_unique<OpenpiSession>(session);
  } catch (const std::runtime_error& error) {
    throw std::runtime_error("policy server " + server + " is not reachable: " + error.what());
  }
}

}  // namespace

RemotePolicy::RemotePolicy(RemotePolicyOptions options, int num_envs)
    : options_(std::move(options)), queues_(static_cast<std::size_t>(num_envs)) {
  if (options_.servers.empty()) throw std::invalid_argument("a served policy needs at least one server URL");
  if (options_.replan_steps < 0) {
    throw std::invalid_argument("--replan-steps must be >= 0 (0: the whole chunk), got " + std::to_string(options_.replan_steps));
  }
  for (const std::string& server : options_.servers) sessions_.push_back(OpenWhenReady(server, options_));
}

void RemotePolicy::Reset(const batch::Observation&, const std::vector<uint8_t>& started) {
  for (std::size_t env = 0; env < queues_.size(); ++env) {
    if (started[env]) queues_[env].clear();
  }
  for (const std::unique_ptr<OpenpiSession>& session : sessions_) session->ServiceKeepalive();
}

void RemotePolicy::Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
                       batch::ActionBatch& actions) {
  for (int env = 0; env < static_cast<int>(queues_.size()); ++env) {
    if (!acting[static_cast<std::size_t>(env)]) continue;
    std::deque<kinematics::Action>& queue = queues_[static_cast<std::size_t>(env)];
    if (queue.empty() && !Query(observation, env)) continue;
    actions[static_cast<std::size_t>(env)] = queue.front();
    queue.pop_front();
  }
}

void RemotePolicy::TakeFaults(std::vector<batch::PolicyFault>& faults) {
  for (batch::PolicyFault& fault : faults_) faults.push_back(std::move(fault));
  faults_.clear();
}

bool RemotePolicy::Query(const batch::Observation& observation, int env) {
  InferResult result;
  try {
    const std::vector<std::string> sent = batch::ProtocolCameras(cameras(), options_.protocol);
    result = SessionOf(env).Infer(BuildRequest(observation, options_.keys, sent, env));
  } catch (const MalformedReply& error) {
    faults_.push_back({env, "server " + ServerOf(env) + ": " + error.what()});  // ends only this episode
    return false;
  } catch (const std::exception& error) {
    throw std::runtime_error("policy 'openpi', " + EnvContext(observation, env, ServerOf(env)) + ": " + error.what());
  }
  timings_.round_trip_ms.push_back(result.round_trip_ms);
  if (const auto server_ms = ReadReplyTimings(result.reply).server_infer_ms) timings_.server_infer_ms.push_back(*server_ms);
  ActionChunk chunk;
  try {
    chunk = ReadActionChunk(result.reply);
    if (chunk.dim != kinematics::action::kSize || chunk.horizon < 1) {
      throw std::invalid_argument("reply actions are " + std::to_string(chunk.horizon) + " x " + std::to_string(chunk.dim) +
                                  ", expected H x " + std::to_string(kinematics::action::kSize) + " with H >= 1");
    }
  } catch (const std::invalid_argument& error) {
    faults_.push_back({env, "server " + ServerOf(env) + ": " + error.what()});
    return false;
  }
  const int rows = options_.replan_steps > 0 ? std::min(options_.replan_steps, chunk.horizon) : chunk.horizon;
  std::deque<kinematics::Action>& queue = queues_[static_cast<std::size_t>(env)];
  for (int row = 0; row < rows; ++row) {
    kinematics::Action action;
    for (int column = 0; column < chunk.dim; ++column) action[static_cast<std::size_t>(column)] = chunk.at(row, column);
    queue.push_back(action);
  }
  return true;
}

std::vector<Value> RemotePolicy::server_metadata() const {
  std::vector<Value> metadata;
  for (const std::unique_ptr<OpenpiSession>& session : sessions_) metadata.push_back(session->metadata());
  return metadata;
}

RequestTimings RemotePolicy::timings() const {
  RequestTimings timings = timings_;
  timings.reconnects = 0;
  for (const std::unique_ptr<OpenpiSession>& session : sessions_) timings.reconnects += session->reconnects();
  return timings;
}

}  // namespace tavis::remote
