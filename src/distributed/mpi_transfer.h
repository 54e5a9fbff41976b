// Films of chunk-tree nodes, with the reports of the ranks whose samples they hold, going
// from one rank to another: a JSON header, then each film's arrays sent straight from (and
// received straight into) the FilmState vectors, losslessly, so a merge gives the same bits
// wherever it happens. Per pixel: mean and M2 (2 x 3 doubles), luminance mean and M2 (2
// floats), the count (uint32) and, when kept, the feature sums (7 floats): 60 or 88 bytes.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "src/distributed/chunk_tree.h"
#include "src/distributed/film_pool.h"
#include "src/distributed/mpi_comm.h"

namespace pt::mpi {

using NodeFilms = std::vector<std::pair<ChunkNode, FilmState>>;

class FilmTransferOut {
 public:
  FilmTransferOut(MPI_Comm comm, int dest, const std::vector<RankReport>& reports,
                  NodeFilms films);
  bool Done();  // tests the sends
  int Dest() const { return dest_; }

 private:
  std::string header_;
  NodeFilms films_;
  std::vector<MPI_Request> requests_;
  int dest_;
};

class FilmTransferIn {
 public:
  // A header waiting from `source` (or MPI_ANY_SOURCE): received, and the arrays' receives
  // posted, into films from `pool` when it has some. Null when none is waiting. Throws
  // MpiFailure on a malformed header.
  static std::unique_ptr<FilmTransferIn> TryStart(MPI_Comm comm, int source,
                                                  FilmPool* pool = nullptr);
  bool Done();  // tests the receives
  // Stops waiting for a sender that is gone: cancels the receives.
  void Cancel();
  int Source() const { return source_; }
  NodeFilms TakeFilms() { return std::move(films_); }
  const std::vector<RankReport>& Reports() const { return reports_; }

 private:
  int source_ = 0;
  NodeFilms films_;
  std::vector<RankReport> reports_;
  std::vector<MPI_Request> requests_;
};

}  // namespace pt::mpi
