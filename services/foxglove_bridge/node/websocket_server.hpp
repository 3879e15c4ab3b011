// The WebSocket side of the bridge (Boost.Beast, from the Boost the project already
// installs): accepts clients that offer foxglove.websocket.v1, hands their text frames to
// the bridge and sends each client's frames from its own bounded SendQueue on one I/O
// thread, so a slow client only ever fills its own queue.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "scanbus/foxglove_bridge/channels.hpp"
#include "scanbus/foxglove_bridge/send_queue.hpp"

namespace scanbus::foxglove_bridge {

class Session;

// 127.0.0.0/8 or ::1; false for what is not an IP address.
bool is_loopback_address(const std::string& address);

struct ServerSettings {
  std::string address = "127.0.0.1";
  uint16_t port = 8765;                   // 0: any free port (port() says which)
  size_t client_queue_bytes = 64u << 20;  // per client; beyond it older samples are dropped
};

struct ClientQueue {
  ClientId client = 0;
  std::string remote;  // address:port
  size_t queued_bytes = 0;
  uint64_t dropped = 0;
  std::map<uint32_t, uint64_t> dropped_by_channel;
};

class WebSocketServer {
 public:
  struct Handlers {
    std::function<void(ClientId)> opened;                    // the handshake is done
    std::function<void(ClientId, const std::string&)> text;  // a text frame from the client
    std::function<void(ClientId, const ClientQueue&)>
        closed;  // gone (closed, reset, failed write): its last queue state
  };

  // Binds and listens; throws std::runtime_error naming the address and port it cannot bind.
  // Clients are accepted from start() on, and no handler runs after stop() (or the end).
  WebSocketServer(const ServerSettings& settings, Handlers handlers);
  ~WebSocketServer();
  void start();
  void stop();
  WebSocketServer(const WebSocketServer&) = delete;
  WebSocketServer& operator=(const WebSocketServer&) = delete;

  uint16_t port() const { return port_; }
  // Queues a frame for a client (thread-safe; a client already gone is ignored).
  void send(ClientId client, Frame frame);
  std::vector<ClientQueue> queues() const;

 private:
  friend class Session;
  void accept();
  void closed(ClientId client, const ClientQueue& last);
  bool stopped_ = false;

  struct Io;
  std::unique_ptr<Io> io_;
  Handlers handlers_;
  size_t client_queue_bytes_;
  uint16_t port_ = 0;
  ClientId next_client_ = 1;
  mutable std::mutex mutex_;
  std::map<ClientId, std::shared_ptr<Session>> sessions_;
  std::thread thread_;
};

}  // namespace scanbus::foxglove_bridge
