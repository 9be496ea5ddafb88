// Streaming calls and the clients that stall them. A sync gRPC handler holds a server thread while
// it waits in Read() or Write(), so a client that opens streams and then sends (or reads) nothing
// would hold every thread. Each streaming call therefore opens a Call here: at most maxOpen are
// open at once (past that the call is refused at once with RESOURCE_EXHAUSTED and a retry hint,
// leaving threads for everything else), and a watchdog cancels a call that has waited on its
// client longer than the limit for that wait. Time the server spends working (parsing,
// tessellating) does not count: only the waits inside read() and write().
#pragma once

#include <grpcpp/server_context.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <mutex>
#include <string>
#include <thread>

namespace tessera::server {

class StreamWatch {
 public:
  using Clock = std::chrono::steady_clock;
  struct Limits {
    int maxOpen = 256;
    Clock::duration idle = std::chrono::seconds(30);  // a message expected, or one being sent
    Clock::duration sessionIdle = std::chrono::minutes(10);  // a render session's next camera
  };

 private:
  struct Entry {
    grpc::ServerContext* context;
    std::string method;
    Clock::duration readLimit;
    std::atomic<int64_t> readSince{0}, writeSince{0};  // Clock ticks; 0: not waiting
  };

 public:
  // One streaming call's registration; destroying it (before the handler returns) ends the watch.
  class Call {
   public:
    Call(Call&& other) noexcept : owner_(other.owner_), entry_(other.entry_) { other.owner_ = nullptr; }
    Call& operator=(Call&&) = delete;
    ~Call();

    // Read() and Write() with the wait watched.
    template <class Reader, class Message>
    bool read(Reader& reader, Message* message) {
      Waiting waiting(entry_->readSince);
      return reader.Read(message);
    }
    template <class Writer, class Message>
    bool write(Writer& writer, const Message& message) {
      Waiting waiting(entry_->writeSince);
      return writer.Write(message);
    }

   private:
    friend class StreamWatch;
    Call(StreamWatch* owner, std::list<Entry>::iterator entry) : owner_(owner), entry_(entry) {}
    struct Waiting {
      explicit Waiting(std::atomic<int64_t>& since) : since_(since) {
        since_.store(Clock::now().time_since_epoch().count());
      }
      ~Waiting() { since_.store(0); }
      std::atomic<int64_t>& since_;
    };
    StreamWatch* owner_;
    std::list<Entry>::iterator entry_;
  };

  explicit StreamWatch(Limits limits);
  StreamWatch(const StreamWatch&) = delete;
  StreamWatch& operator=(const StreamWatch&) = delete;
  ~StreamWatch();

  // Registers a streaming call (`session`: a render session, whose client may pause longer).
  // Throws StatusError(RESOURCE_EXHAUSTED, retry hint) when maxOpen calls are open.
  Call open(grpc::ServerContext& context, const std::string& method, bool session = false);
  int openCalls() const;
  uint64_t cancelledCalls() const;

 private:
  void watch();

  const Limits limits_;
  mutable std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  std::list<Entry> open_;
  uint64_t cancelled_ = 0;
  std::thread watchdog_;
};

// A stream whose Read() and Write() go through a Call's watch, for code written against the
// stream's own interface.
template <class Stream>
class Watched {
 public:
  Watched(Stream& stream, StreamWatch::Call& call) : stream_(stream), call_(call) {}
  template <class Message>
  bool Read(Message* message) {
    return call_.read(stream_, message);
  }
  template <class Message>
  bool Write(const Message& message) {
    return call_.write(stream_, message);
  }

 private:
  Stream& stream_;
  StreamWatch::Call& call_;
};

}  // namespace tessera::server
