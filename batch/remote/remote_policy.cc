#include "batch/remote/remote_policy.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <thread>

#include "batch/observation_contract.h"
#include "batch/remote/health_probe.h"
#include "batch/remote/openpi_reply.h"
#include "batch/remote/remote_error.h"
#include "batch/remote/server_contract.h"
#include "batch/remote/websocket_url.h"
#include "kinematics/enum_names.h"

namespace tavis::batch::remote {
namespace {

std::string EnvContext(const batch::Observation& observation, const std::vector<int>& envs, const std::string& server) {
  std::string slots, episodes;
  for (std::size_t i = 0; i < envs.size(); ++i) {
    slots += (i > 0 ? ", " : "") + std::to_string(envs[i]);
    episodes += (i > 0 ? ", " : "") + std::to_string(observation.state.episode[envs[i]]);
  }
  return (envs.size() == 1 ? "env slot " : "env slots ") + slots + (envs.size() == 1 ? " (episode " : " (episodes ") +
         episodes + ", server " + server + ")";
}

// Waits for the server (its /healthz, or its socket when it has none), then connects.
std::unique_ptr<OpenpiSession> OpenWhenReady(const std::string& server, const RemotePolicyOptions& options,
                                             bool announce_fallback) {
  const WebSocketUrl url = ParseWebSocketUrl(server);
  try {
    if (WaitForHealthz(url, options.ready_timeout) == Readiness::kNoHealthz && announce_fallback) {
      std::cerr << "policy server " << server << " has no /healthz; connecting to it directly\n";
    }
    OpenpiSessionOptions session;
    session.url = server;
    session.reply_timeout = options.reply_timeout;
    session.max_reply_bytes = options.max_reply_bytes;
    return std::make_unique<OpenpiSession>(session);
  } catch (const std::runtime_error& error) {
    throw std::runtime_error("policy server " + server + " is not reachable: " + error.what());
  }
}

constexpr kinematics::EnumName<ServingMode> kServingModes[] = {
    {ServingMode::kSerial, "serial"}, {ServingMode::kPerEnv, "per-env"}, {ServingMode::kBatched, "batched"}};

bool DeclaresBatchedRequests(const Value& metadata) {
  const Value* flag = metadata.Find(batch::contract::kBatchedRequestsMetadata);
  return flag != nullptr && flag->is<bool>() && *flag->get_if<bool>();
}

// Every server's declared contract must agree with what the cell sends: a contradiction is refused
// before the first episode, naming both values.
void CheckDeclaredContracts(const std::vector<std::unique_ptr<OpenpiSession>>& sessions,
                            const RemotePolicyOptions& options) {
  for (std::size_t i = 0; i < sessions.size() && i < options.servers.size(); ++i) {
    const std::optional<ServerContract> contract = ParseServerContract(sessions[i]->metadata(), options.servers[i]);
    if (!contract) continue;
    const int state_size = options.state_size > 0 ? options.state_size : contract->state_size;
    std::vector<std::string> conflicts = TrainedForConflicts(*contract, options.task, options.robot);
    for (std::string& conflict : ContractConflicts(*contract, options.keys, options.replan_steps, state_size)) {
      conflicts.push_back(std::move(conflict));
    }
    if (conflicts.empty()) continue;
    std::string lines;
    for (const std::string& conflict : conflicts) lines += "\n  " + conflict;
    throw std::invalid_argument("the cell contradicts the contract policy server " + options.servers[i] +
                                " declares:" + lines);
  }
}

}  // namespace

Value ReadServerMetadata(const std::string& server, const RemotePolicyOptions& options) {
  return OpenWhenReady(server, options, /*announce_fallback=*/false)->metadata();
}

const char* ToString(ServingMode mode) { return kinematics::NameOf(kServingModes, mode, "?"); }

ServingMode ParseServingMode(const std::string& text) {
  if (const auto* mode = kinematics::FindNamed(kServingModes, text)) return mode->value;
  throw std::invalid_argument("unknown serving mode '" + text + "' (known: " + kinematics::NameList(kServingModes) +
                              ")");
}

RemotePolicy::RemotePolicy(RemotePolicyOptions options, int num_envs)
    : options_(std::move(options)), queues_(static_cast<std::size_t>(num_envs)) {
  if (options_.servers.empty()) throw std::invalid_argument("a served policy needs at least one server URL");
  if (options_.replan_steps < 0) {
    throw std::invalid_argument("replan_steps must be at least 0 (0: the whole chunk), got " +
                                std::to_string(options_.replan_steps));
  }
  const int sessions = options_.mode == ServingMode::kPerEnv ? num_envs : static_cast<int>(options_.servers.size());
  for (int i = 0; i < sessions; ++i) {
    const std::string& server = options_.servers[static_cast<std::size_t>(i) % options_.servers.size()];
    sessions_.push_back(OpenWhenReady(server, options_, i < static_cast<int>(options_.servers.size())));
  }
  CheckDeclaredContracts(sessions_, options_);
  if (options_.mode == ServingMode::kBatched) {
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      if (!DeclaresBatchedRequests(sessions_[i]->metadata())) {
        throw std::invalid_argument(
            "policy server " + options_.servers[i] + " does not declare \"" +
            batch::contract::kBatchedRequestsMetadata +
            "\": true in its metadata, so it may not understand batched requests; serve it with "
            "serving serial or per-env");
      }
    }
  }
}

OpenpiSession& RemotePolicy::SessionOf(int env) {
  const int index = options_.mode == ServingMode::kPerEnv ? env : ServerIndexOf(env);
  return *sessions_[static_cast<std::size_t>(index)];
}

void RemotePolicy::Reset(const batch::Observation&, const std::vector<uint8_t>& started) {
  for (std::size_t env = 0; env < queues_.size(); ++env) {
    if (started[env]) queues_[env].clear();
  }
  // Keeping a connection alive may have to reconnect to a server that died between requests:
  // the error names the server, as a failed request's does.
  for (std::size_t i = 0; i < sessions_.size(); ++i) {
    try {
      sessions_[i]->ServiceKeepalive();
    } catch (const std::runtime_error& error) {
      throw std::runtime_error("policy 'openpi', server " + options_.servers[i % options_.servers.size()] + ": " +
                               error.what());
    }
  }
}

std::vector<RemotePolicy::Exchange> RemotePolicy::PlanExchanges(const batch::Observation& observation,
                                                                const std::vector<int>& due) {
  const std::vector<std::string> sent = batch::ProtocolCameras(cameras(), options_.protocol);
  std::vector<Exchange> exchanges;
  if (options_.mode != ServingMode::kBatched) {
    for (int env : due) {
      Exchange exchange;
      exchange.envs = {env};
      exchange.session = &SessionOf(env);
      exchange.server = &options_.servers[static_cast<std::size_t>(ServerIndexOf(env))];
      exchange.request = BuildRequest(observation, options_.keys, sent, env);
      exchanges.push_back(std::move(exchange));
    }
    return exchanges;
  }
  for (int server = 0; server < static_cast<int>(options_.servers.size()); ++server) {
    Exchange exchange;
    for (int env : due) {
      if (ServerIndexOf(env) == server) exchange.envs.push_back(env);
    }
    if (exchange.envs.empty()) continue;
    exchange.session = sessions_[static_cast<std::size_t>(server)].get();
    exchange.server = &options_.servers[static_cast<std::size_t>(server)];
    exchange.request = BuildBatchRequest(observation, options_.keys, sent, exchange.envs);
    exchanges.push_back(std::move(exchange));
  }
  return exchanges;
}

void RemotePolicy::RunExchanges(std::vector<Exchange>& exchanges) const {
  const auto run = [](Exchange& exchange) {
    try {
      exchange.result = exchange.session->Infer(exchange.request);
    } catch (...) {
      exchange.error = std::current_exception();
    }
  };
  if (options_.mode == ServingMode::kSerial || exchanges.size() == 1) {
    for (Exchange& exchange : exchanges) {
      run(exchange);
      if (exchange.error) return;  // stop at the first failure, as one request after the other would
    }
    return;
  }
  // Each exchange has a session of its own (per env, or per server when batched), so they can
  // wait side by side; the replies are taken in env order afterwards.
  std::vector<std::thread> threads;
  threads.reserve(exchanges.size());
  for (Exchange& exchange : exchanges) threads.emplace_back(run, std::ref(exchange));
  for (std::thread& thread : threads) thread.join();
}

void RemotePolicy::Act(const batch::Observation& observation, const std::vector<uint8_t>& acting,
                       batch::ActionBatch& actions) {
  std::vector<int> due;
  for (int env = 0; env < static_cast<int>(queues_.size()); ++env) {
    if (acting[static_cast<std::size_t>(env)] && queues_[static_cast<std::size_t>(env)].empty()) due.push_back(env);
  }
  if (!due.empty()) {
    std::vector<Exchange> exchanges = PlanExchanges(observation, due);
    const auto start = std::chrono::steady_clock::now();
    RunExchanges(exchanges);
    timings_.wait_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++timings_.policy_ticks;
    for (Exchange& exchange : exchanges) {
      if (exchange.error) {
        try {
          std::rethrow_exception(exchange.error);
        } catch (const MalformedReply& error) {
          // A reply that is not a well-formed map ends only the episodes it answers.
          for (int env : exchange.envs) faults_.push_back({env, "server " + *exchange.server + ": " + error.what()});
          continue;
        } catch (const std::exception& error) {
          throw std::runtime_error("policy 'openpi', " + EnvContext(observation, exchange.envs, *exchange.server) +
                                   ": " + error.what());
        }
      }
      TakeReply(observation, exchange);
    }
  }
  for (int env = 0; env < static_cast<int>(queues_.size()); ++env) {
    std::deque<kinematics::Action>& queue = queues_[static_cast<std::size_t>(env)];
    if (!acting[static_cast<std::size_t>(env)] || queue.empty()) continue;  // empty: its reply was a fault
    actions[static_cast<std::size_t>(env)] = queue.front();
    queue.pop_front();
  }
}

void RemotePolicy::TakeFaults(std::vector<batch::PolicyFault>& faults) {
  for (batch::PolicyFault& fault : faults_) faults.push_back(std::move(fault));
  faults_.clear();
}

void RemotePolicy::TakeReply(const batch::Observation&, Exchange& exchange) {
  const InferResult& result = exchange.result;
  timings_.round_trip_ms.push_back(result.round_trip_ms);
  timings_.envs_per_request.push_back(static_cast<int>(exchange.envs.size()));
  if (const auto server_ms = ReadReplyTimings(result.reply).server_infer_ms)
    timings_.server_infer_ms.push_back(*server_ms);
  std::vector<ActionChunk> chunks;
  try {
    if (options_.mode == ServingMode::kBatched) {
      chunks = ReadBatchedActionChunks(result.reply, static_cast<int>(exchange.envs.size()));
    } else {
      chunks.push_back(ReadActionChunk(result.reply));
    }
    const ActionChunk& chunk = chunks.front();
    if (chunk.dim != kinematics::action::kSize || chunk.horizon < 1) {
      throw std::invalid_argument("reply actions are " + std::to_string(chunk.horizon) + " x " +
                                  std::to_string(chunk.dim) + ", expected H x " +
                                  std::to_string(kinematics::action::kSize) + " with H >= 1");
    }
  } catch (const std::invalid_argument& error) {
    for (int env : exchange.envs) faults_.push_back({env, "server " + *exchange.server + ": " + error.what()});
    return;
  }
  for (std::size_t i = 0; i < exchange.envs.size(); ++i) QueueRows(exchange.envs[i], chunks[i]);
}

void RemotePolicy::QueueRows(int env, const ActionChunk& chunk) {
  const int rows = options_.replan_steps > 0 ? std::min(options_.replan_steps, chunk.horizon) : chunk.horizon;
  std::deque<kinematics::Action>& queue = queues_[static_cast<std::size_t>(env)];
  for (int row = 0; row < rows; ++row) {
    kinematics::Action action;
    for (int column = 0; column < chunk.dim; ++column) action[static_cast<std::size_t>(column)] = chunk.at(row, column);
    queue.push_back(action);
  }
}

std::vector<Value> RemotePolicy::server_metadata() const {
  // Per-env mode opens several sessions to a server; the first of each stands for it.
  std::vector<Value> metadata;
  for (std::size_t i = 0; i < options_.servers.size(); ++i) metadata.push_back(sessions_[i]->metadata());
  return metadata;
}

RequestTimings RemotePolicy::timings() const {
  RequestTimings timings = timings_;
  timings.reconnects = 0;
  for (const std::unique_ptr<OpenpiSession>& session : sessions_) timings.reconnects += session->reconnects();
  return timings;
}

}  // namespace tavis::batch::remote
