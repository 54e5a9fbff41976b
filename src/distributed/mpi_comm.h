// MPI plumbing shared by src/distributed/mpi_*.cpp (built only with MPI): the job on a
// duplicated communicator whose errors return instead of aborting, the message tags, and
// non-blocking sends that own their bytes. Nothing here waits without a way out.
#pragma once

#include <mpi.h>

#include <list>
#include <string>
#include <vector>

#include "src/distributed/distributed.h"

namespace pt::mpi {

// Throws MpiFailure naming the call when code is not MPI_SUCCESS.
void Check(int code, const char* what);

enum Tag : int {
  kTagRequest = 101,    // worker -> 0: int32 lane wants a leaf
  kTagGrant,            // 0 -> worker: int32 {lane, leaf or -1 = none}
  kTagProgress,         // worker -> 0: uint64 samples so far (also says "alive")
  kTagEvent,            // worker -> 0: int32 kind, then int32 signal or text (interrupted, failed)
  kTagStop,             // 0 -> worker: int32 StopReason
  kTagHeartbeat,        // 0 -> worker: int32 0 (rank 0 is alive)
  kTagHandedOver,       // worker -> 0: int32 parent (its films went up the tree)
  kTagWentToRoot,       // worker -> its tree parent: its films went straight to rank 0
  kTagReduceHeader,     // films and reports going up: JSON text
  kTagReduceData,       // ... followed by the films' arrays
  kTagDone,             // 0 -> worker: int32 the job's exit status
};

enum EventKind : int { kEventInterrupted = 1, kEventFailed = 2 };
enum StopReason : int { kStopNone = 0, kStopTimeLimit, kStopInterrupt, kStopFailure, kStopLost };

class MpiJobImpl final : public MpiJob {
 public:
  MpiJobImpl();
  ~MpiJobImpl() override;

  int Rank() const override { return rank_; }
  int Size() const override { return size_; }
  int LocalRank() const override { return localRank_; }
  int LocalSize() const override { return localSize_; }
  std::string Host() const override { return host_; }
  std::pair<int, std::string> Agree(int status, const std::string& message) override;
  std::vector<uint64_t> AllGather(uint64_t value) override;
  int ShareExitStatus(int status, const StopSignalSource& stopSignal) override;
  [[noreturn]] void Abort(int status) override;

  MPI_Comm Comm() const { return comm_; }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1, localRank_ = 0, localSize_ = 1;
  std::string host_;
};

// Small messages sent without waiting; each keeps its bytes until MPI is done with them.
class Outbox {
 public:
  explicit Outbox(MPI_Comm comm) : comm_(comm) {}
  void Send(int dest, int tag, std::vector<char> bytes);
  template <typename T>
  void SendValue(int dest, int tag, const T& value) {
    const char* p = reinterpret_cast<const char*>(&value);
    Send(dest, tag, std::vector<char>(p, p + sizeof(T)));
  }
  // Completes what it can; returns the sends still pending.
  size_t Progress();

 private:
  struct Pending {
    std::vector<char> bytes;
    MPI_Request request;
  };
  MPI_Comm comm_;
  std::list<Pending> pending_;
};

// A message of `tag` from `source` (MPI_ANY_SOURCE for any) waiting to be received: its
// bytes, and the rank it came from. False when none is waiting.
bool TryReceive(MPI_Comm comm, int source, int tag, std::vector<char>* bytes, int* from);

template <typename T>
T ValueOf(const std::vector<char>& bytes, size_t at = 0) {
  T value{};
  if (bytes.size() >= at + sizeof(T)) std::copy_n(bytes.data() + at, sizeof(T),
                                                  reinterpret_cast<char*>(&value));
  return value;
}

}  // namespace pt::mpi
