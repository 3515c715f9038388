// The `set` and `action` commands: their subscription, their checks on arrival, the
// thread that runs them, and their answers on the result and response topics.
#include "mqtt/bridge_impl.hpp"

#include <mqtt_protocol.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <utility>

#include "mqtt/command_answer.hpp"
#include "mqtt/sensor_link.hpp"
#include "rangekit/hub/json_views.hpp"

namespace rangekit::mqtt {
namespace {

// A command is a few settings or one action name; anything longer is refused unread and not queued.
constexpr std::size_t max_command_bytes = std::size_t{16} * 1024;

}  // namespace

void Bridge::Impl::subscribe_commands(Link& link) {
  // Both command topics in one SUBSCRIBE: the session counts as connected at its SUBACK.
  const std::string set_topic = link.topic + "/set";
  const std::string action_topic = link.topic + "/action";
  std::array<char*, 2> topics{const_cast<char*>(set_topic.c_str()), const_cast<char*>(action_topic.c_str())};
  link.subscribe_mid = -1;
  // Retained commands are never sent to it (MQTT 5 retain handling 2): they would run at every connect.
  mosquitto_subscribe_multiple(link.client, &link.subscribe_mid, static_cast<int>(topics.size()), topics.data(),
                               options.config.qos_command, MQTT_SUB_OPT_SEND_RETAIN_NEVER, nullptr);
}

// On the network thread: a message on `set` or `action` becomes a Command, refused at once
// when it must not run, queued for the command thread, or answered `busy` when the queue is full.
void Bridge::Impl::receive_command(Link& link, const mosquitto_message& message, const mosquitto_property* props) {
  Command command;
  command.link = &link;
  const std::string topic = message.topic;
  if (topic == link.topic + "/set") {
    command.is_set = true;
  } else if (topic == link.topic + "/action") {
    command.is_set = false;
  } else {
    return;
  }
  const auto size = static_cast<std::size_t>(std::max(message.payloadlen, 0));
  const auto refuse = [&](std::string code, std::string why, std::string field = {}) {
    command.refusal = Command::Refusal{std::move(code), std::move(why), std::move(field)};
  };
  if (message.retain) {
    // A retained command would run again at every connect of every service that subscribes.
    refuse("retained",
           "a retained command is not run: publish it without the retain flag, and clear the retained one with an "
           "empty retained message to " +
               topic);
  } else if (size > max_command_bytes) {
    refuse("too_large", "a command of " + std::to_string(size) + " bytes is not run: at most " +
                            std::to_string(max_command_bytes) + " bytes");
  } else if (size > 0) {
    command.payload.assign(static_cast<const char*>(message.payload), size);
  }
  char* response = nullptr;
  if (mosquitto_property_read_string(props, MQTT_PROP_RESPONSE_TOPIC, &response, false) != nullptr &&
      response != nullptr) {
    command.response_topic = response;
    free(response);  // NOLINT(cppcoreguidelines-no-malloc): libmosquitto allocates it with malloc
  }
  // Answers go out under the service's own rights, so only to topics made for them.
  if (const std::string reply_root = options.config.base_topic + "/reply/";
      !command.response_topic.empty() && !command.response_topic.starts_with(reply_root)) {
    if (!command.refusal) {
      refuse("bad_response_topic",
             "the response topic '" + command.response_topic + "' is not under " + reply_root + ": nothing was run",
             "response_topic");
    }
    command.response_topic.clear();
  }
  void* correlation = nullptr;
  std::uint16_t length = 0;
  if (mosquitto_property_read_binary(props, MQTT_PROP_CORRELATION_DATA, &correlation, &length, false) != nullptr &&
      correlation != nullptr) {
    command.correlation.assign(static_cast<const char*>(correlation), length);
    free(correlation);  // NOLINT(cppcoreguidelines-no-malloc)
  }
  bool queued = false;
  {
    const std::lock_guard lock(command_mutex);
    if (commands.size() < options.max_queued_commands) {
      commands.push_back(std::move(command));
      queued = true;
    }
  }
  if (queued) {
    command_ready.notify_one();
    return;
  }
  // A flood of commands is not queued without end: the one over the bound is answered now.
  ++busy;
  answer(command, hub::error_object("busy", std::to_string(options.max_queued_commands) +
                                                " commands are waiting already: this one was not run; "
                                                "send it again once they are answered"));
}

void Bridge::Impl::run_commands() {
  while (true) {
    Command command;
    {
      std::unique_lock lock(command_mutex);
      command_ready.wait(lock, [&] { return stopping || !commands.empty(); });
      if (commands.empty()) return;
      command = std::move(commands.front());
      commands.pop_front();
    }
    handle(command);
  }
}

void Bridge::Impl::handle(Command& command) {
  nlohmann::json result;
  try {
    result = result_of(command);
  } catch (const std::exception& e) {
    // Nothing leaves the command thread: a command that fails this way is answered, and the next one runs.
    result = hub::error_object("internal", std::string("the command could not be run: ") + e.what());
  }
  ++handled;
  answer(command, std::move(result));
}

void Bridge::Impl::answer(Command& command, nlohmann::json result) {
  Link& link = *command.link;
  if (result.contains("error")) result["ok"] = false;
  {
    const std::lock_guard lock(reply_mutex);
    replies.push_back(Reply{&link, link.topic + (command.is_set ? "/set/result" : "/action/result"),
                            result.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                            std::move(command.response_topic), std::move(command.correlation)});
  }
  link.status_now = true;  // settings may have changed: the status goes out again at once
  wake();
}

nlohmann::json Bridge::Impl::result_of(const Command& command) {
  if (command.refusal)
    return hub::error_object(command.refusal->code, command.refusal->message, command.refusal->field);
  return answer_command(hub, command.link->config.name, command.is_set ? CommandKind::set : CommandKind::action,
                        command.payload);
}

void Bridge::Impl::send_replies() {
  std::deque<Reply> ready;
  {
    const std::lock_guard lock(reply_mutex);
    ready.swap(replies);
  }
  const int qos = options.config.qos_command;
  std::deque<Reply> later;  // a session with part of a fast-path packet on the wire writes nothing else
  for (Reply& reply : ready) {
    Link& link = *reply.link;
    if (link.out.mid_packet()) {
      later.push_back(std::move(reply));
      continue;
    }
    if (!reply.response_topic.empty()) {
      // MQTT 5 request/response: the answer on the asked topic, with the request's correlation data.
      mosquitto_property* props = nullptr;
      if (!reply.correlation.empty()) {
        mosquitto_property_add_binary(&props, MQTT_PROP_CORRELATION_DATA, reply.correlation.data(),
                                      static_cast<std::uint16_t>(reply.correlation.size()));
      }
      if (link.connected && mosquitto_publish_v5(link.client, nullptr, reply.response_topic.c_str(),
                                                 static_cast<int>(reply.payload.size()), reply.payload.data(), qos,
                                                 false, props) == MOSQ_ERR_SUCCESS) {
        ++link.published;
      }
      mosquitto_property_free_all(&props);
    }
    link.send(Message{std::move(reply.topic), std::move(reply.payload), qos, false});
  }
  if (later.empty()) return;
  const std::lock_guard lock(reply_mutex);
  for (auto it = later.rbegin(); it != later.rend(); ++it) replies.push_front(std::move(*it));
}

}  // namespace rangekit::mqtt
