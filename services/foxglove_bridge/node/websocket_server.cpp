#include "websocket_server.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <array>
#include <chrono>
#include <stdexcept>

namespace scanbus::foxglove_bridge {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

struct WebSocketServer::Io {
  net::io_context context{1};
  tcp::acceptor acceptor{context};
  net::steady_timer retry{context};  // accepting again after an error (out of descriptors)
};

namespace {

// The Sec-WebSocket-Protocol list ("a, b") holds ours as a whole token.
bool offers_subprotocol(beast::string_view offered) {
  while (!offered.empty()) {
    const size_t comma = offered.find(',');
    beast::string_view token = offered.substr(0, comma);
    while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
    while (!token.empty() && token.back() == ' ') token.remove_suffix(1);
    if (token == kSubprotocol) return true;
    if (comma == beast::string_view::npos) break;
    offered.remove_prefix(comma + 1);
  }
  return false;
}

}  // namespace

bool is_loopback_address(const std::string& address) {
  beast::error_code error;
  const auto parsed = net::ip::make_address(address, error);
  return !error && parsed.is_loopback();
}

// One client: the HTTP upgrade, then a read loop and a write loop on the server's I/O
// thread. Frames come in from any thread through push(); only the I/O thread writes.
class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, ClientId id, WebSocketServer& server)
      : ws_(std::move(socket)), id_(id), server_(server), queue_(server.client_queue_bytes_) {
    beast::error_code error;
    const auto endpoint = beast::get_lowest_layer(ws_).socket().remote_endpoint(error);
    if (!error) remote_ = endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
  }

  void start() { read_request(); }

  void push(Frame frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!queue_.push(std::move(frame))) {  // asks and never reads: nothing bounds what it is owed
      net::post(ws_.get_executor(), [self = shared_from_this()] { self->finish(); });
      return;
    }
    if (open_ && !writing_) {
      writing_ = true;  // a write is on its way: later pushes only queue
      net::post(ws_.get_executor(), [self = shared_from_this()] { self->write_next(); });
    }
  }

  ClientQueue state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return {id_, remote_, queue_.bytes(), queue_.dropped(), queue_.dropped_by_channel()};
  }

 private:
  void read_request() {
    beast::get_lowest_layer(ws_).expires_after(std::chrono::seconds(30));  // a handshake that stalls
    http::async_read(beast::get_lowest_layer(ws_), buffer_, request_,
                     [self = shared_from_this()](beast::error_code error, size_t) { self->on_request(error); });
  }

  void on_request(beast::error_code error) {
    if (error) return finish();
    if (!websocket::is_upgrade(request_) || !offers_subprotocol(request_[http::field::sec_websocket_protocol]))
      return refuse("this is a Foxglove WebSocket server: connect with the subprotocol " + std::string(kSubprotocol));
    beast::get_lowest_layer(ws_).expires_never();  // the websocket's own timeouts from here on
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
      response.set(http::field::sec_websocket_protocol, kSubprotocol);
      response.set(http::field::server, "scanbus foxglove_bridge");
    }));
    ws_.auto_fragment(false);       // a sample goes out as one frame, written from where it lies
    ws_.read_message_max(1 << 20);  // clients send small JSON requests
    ws_.async_accept(request_, [self = shared_from_this()](beast::error_code error) { self->on_accept(error); });
  }

  void refuse(const std::string& why) {
    auto response = std::make_shared<http::response<http::string_body>>(http::status::bad_request, request_.version());
    response->set(http::field::content_type, "text/plain");
    response->body() = why + "\n";
    response->prepare_payload();
    http::async_write(beast::get_lowest_layer(ws_), *response,
                      [self = shared_from_this(), response](beast::error_code, size_t) { self->finish(); });
  }

  void on_accept(beast::error_code error) {
    if (error) return finish();
    server_.handlers_.opened(id_);  // queues serverInfo and the channels before anything else
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open_ = true;
      writing_ = true;
    }
    write_next();
    read();
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code error, size_t) { self->on_read(error); });
  }

  void on_read(beast::error_code error) {
    if (error) return finish();
    if (ws_.got_text()) server_.handlers_.text(id_, beast::buffers_to_string(buffer_.data()));
    buffer_.consume(buffer_.size());
    read();
  }

  void write_next() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto frame = queue_.pop();
      if (!frame) {
        writing_ = false;
        return;
      }
      sending_ = std::move(*frame);
    }
    ws_.binary(sending_.binary());
    auto done = [self = shared_from_this()](beast::error_code error, size_t) {
      if (error) return self->finish();
      self->write_next();
    };
    if (!sending_.binary()) return ws_.async_write(net::buffer(sending_.text), std::move(done));
    const std::array<net::const_buffer, 2> parts{
        net::buffer(sending_.header), sending_.payload ? net::buffer(*sending_.payload) : net::const_buffer()};
    ws_.async_write(parts, std::move(done));
  }

  // Once, however the session ends (the read and the write loop may both fail).
  void finish() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (finished_) return;
      finished_ = true;
      open_ = false;
    }
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
    server_.closed(id_, state());
  }

  websocket::stream<beast::tcp_stream> ws_;
  ClientId id_;
  WebSocketServer& server_;
  std::string remote_ = "?";
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  mutable std::mutex mutex_;
  SendQueue queue_;
  bool open_ = false, writing_ = false, finished_ = false;
  Frame sending_;  // the frame being written (its buffers must live until the write completes)
};

WebSocketServer::WebSocketServer(const ServerSettings& settings, Handlers handlers)
    : io_(std::make_unique<Io>()), handlers_(std::move(handlers)), client_queue_bytes_(settings.client_queue_bytes) {
  const std::string where = settings.address + ":" + std::to_string(settings.port);
  beast::error_code error;
  const auto address = net::ip::make_address(settings.address, error);
  if (error) throw std::runtime_error("foxglove_bridge: '" + settings.address + "' is not an IP address");
  const tcp::endpoint endpoint(address, settings.port);
  auto& acceptor = io_->acceptor;
  acceptor.open(endpoint.protocol(), error);
  if (!error) acceptor.set_option(net::socket_base::reuse_address(true), error);
  if (!error) acceptor.bind(endpoint, error);
  if (!error) acceptor.listen(net::socket_base::max_listen_connections, error);
  if (error) throw std::runtime_error("foxglove_bridge: cannot listen on " + where + ": " + error.message());
  port_ = acceptor.local_endpoint().port();
}

void WebSocketServer::start() {
  accept();
  thread_ = std::thread([this] { io_->context.run(); });
}

void WebSocketServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  io_->context.stop();
  if (thread_.joinable()) thread_.join();
  std::map<ClientId, std::shared_ptr<Session>> sessions;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sessions.swap(sessions_);
  }
  sessions.clear();
  io_.reset();  // the handlers still pending hold their sessions: they go with the context
}

WebSocketServer::~WebSocketServer() { stop(); }

void WebSocketServer::accept() {
  io_->acceptor.async_accept([this](beast::error_code error, tcp::socket socket) {
    if (error == net::error::operation_aborted) return;  // closing
    if (error) {                                         // e.g. out of descriptors: try again shortly rather than spin
      io_->retry.expires_after(std::chrono::milliseconds(100));
      io_->retry.async_wait([this](beast::error_code waited) {
        if (!waited) accept();
      });
      return;
    }
    std::shared_ptr<Session> session;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const ClientId id = next_client_++;
      session = std::make_shared<Session>(std::move(socket), id, *this);
      sessions_.emplace(id, session);
    }
    session->start();
    accept();
  });
}

void WebSocketServer::closed(ClientId client, const ClientQueue& last) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sessions_.erase(client);
  }
  handlers_.closed(client, last);
}

void WebSocketServer::send(ClientId client, Frame frame) {
  std::shared_ptr<Session> session;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = sessions_.find(client);
    if (it == sessions_.end()) return;
    session = it->second;
  }
  session->push(std::move(frame));
}

std::vector<ClientQueue> WebSocketServer::queues() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<ClientQueue> list;
  for (const auto& [id, session] : sessions_) list.push_back(session->state());
  return list;
}

}  // namespace scanbus::foxglove_bridge
