// The MPI job: start-up, collectives for agreeing on set-up, the exit status, and aborting.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "src/distributed/mpi_comm.h"

namespace pt {

bool MpiBuilt() { return true; }

std::unique_ptr<MpiJob> MpiJob::Start() { return std::make_unique<mpi::MpiJobImpl>(); }

namespace mpi {

void Check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw MpiFailure(std::string("MPI: ") + what + " failed: " + std::string(text, size_t(length)));
}

MpiJobImpl::MpiJobImpl() {
  int provided = 0;
  int code = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (code != MPI_SUCCESS) throw MpiFailure("MPI_Init_thread failed");
  // Errors come back as codes (turned into exceptions) instead of killing the job silently.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  Check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup");
  Check(MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
  Check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
  Check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
  MPI_Comm local;
  Check(MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local),
        "MPI_Comm_split_type");
  MPI_Comm_rank(local, &localRank_);
  MPI_Comm_size(local, &localSize_);
  MPI_Comm_free(&local);
  char name[MPI_MAX_PROCESSOR_NAME];
  int length = 0;
  MPI_Get_processor_name(name, &length);
  host_.assign(name, size_t(length));
}

MpiJobImpl::~MpiJobImpl() {
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
  MPI_Finalize();
}

std::pair<int, std::string> MpiJobImpl::Agree(int status, const std::string& message) {
  int worst = 0;
  Check(MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, comm_), "MPI_Allreduce");
  if (worst == 0) return {0, ""};
  int mine = status == worst ? rank_ : size_, first = 0;
  Check(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
  std::string text = "rank " + std::to_string(first) + ": " + message;
  int length = int(text.size());
  Check(MPI_Bcast(&length, 1, MPI_INT, first, comm_), "MPI_Bcast");
  text.resize(size_t(length));
  Check(MPI_Bcast(text.data(), length, MPI_CHAR, first, comm_), "MPI_Bcast");
  return {worst, text};
}

std::vector<uint64_t> MpiJobImpl::AllGather(uint64_t value) {
  std::vector<uint64_t> all(size_t(size_), 0);
  Check(MPI_Allgather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, comm_),
        "MPI_Allgather");
  return all;
}

int MpiJobImpl::ShareExitStatus(int status, const StopSignalSource& stopSignal) {
  if (rank_ == 0) {
    Outbox outbox(comm_);
    for (int r = 1; r < size_; ++r) outbox.SendValue(r, kTagDone, int32_t(status));
    while (outbox.Progress() > 0) std::this_thread::sleep_for(std::chrono::microseconds(100));
    return status;
  }
  // Rank 0 may take a while to write the outputs; a dead rank 0 means mpirun tears the job
  // down, which arrives here as SIGTERM.
  std::vector<char> bytes;
  int from = 0;
  while (!TryReceive(comm_, 0, kTagDone, &bytes, &from)) {
    if (stopSignal() != 0) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return ValueOf<int32_t>(bytes);
}

void MpiJobImpl::Abort(int status) {
  std::fflush(stdout);
  std::fflush(stderr);
  MPI_Abort(comm_ != MPI_COMM_NULL ? comm_ : MPI_COMM_WORLD, status);
  std::_Exit(status);
}

void Outbox::Send(int dest, int tag, std::vector<char> bytes) {
  pending_.push_back({std::move(bytes), MPI_REQUEST_NULL});
  Pending& p = pending_.back();
  Check(MPI_Isend(p.bytes.data(), int(p.bytes.size()), MPI_BYTE, dest, tag, comm_, &p.request),
        "MPI_Isend");
}

size_t Outbox::Progress() {
  for (auto it = pending_.begin(); it != pending_.end();) {
    int done = 0;
    Check(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    it = done ? pending_.erase(it) : std::next(it);
  }
  return pending_.size();
}

bool TryReceive(MPI_Comm comm, int source, int tag, std::vector<char>* bytes, int* from) {
  int found = 0;
  MPI_Status status;
  Check(MPI_Iprobe(source, tag, comm, &found, &status), "MPI_Iprobe");
  if (!found) return false;
  int count = 0;
  Check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
  bytes->resize(size_t(count));
  // Probed, so the receive is matched already and returns at once.
  Check(MPI_Recv(bytes->data(), count, MPI_BYTE, status.MPI_SOURCE, tag, comm,
                 MPI_STATUS_IGNORE),
        "MPI_Recv");
  *from = status.MPI_SOURCE;
  return true;
}

}  // namespace mpi
}  // namespace pt
