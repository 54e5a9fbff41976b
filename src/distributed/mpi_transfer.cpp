#include "src/distributed/mpi_transfer.h"

#include <nlohmann/json.hpp>

namespace pt::mpi {
namespace {

static_assert(sizeof(glm::dvec3) == 3 * sizeof(double) && sizeof(vec3) == 3 * sizeof(float),
              "vectors travel as plain arrays");

struct ArrayRef {
  void* data;
  int count;
  MPI_Datatype type;
};

// A film's arrays in the order they travel (resized first when receiving). Every count fits
// an int: images are at most 2^28 pixels.
std::vector<ArrayRef> Arrays(FilmState& f, bool features, bool halves, bool resize) {
  size_t n = f.PixelCount();
  if (resize) {
    f.mean.resize(n);
    f.m2.resize(n);
    f.lumMean.resize(n);
    f.lumM2.resize(n);
    f.count.resize(n);
    f.albedoSum.resize(features ? n : 0);
    f.normalSum.resize(features ? n : 0);
    f.depthSum.resize(features ? n : 0);
    f.evenSum.resize(halves ? n : 0);
    f.evenCount.resize(halves ? n : 0);
    for (std::vector<vec3>* v : {&f.residualMean, &f.residualM2, &f.evenEmissionSum})
      v->resize(halves ? n : 0);
  }
  int n1 = int(n), n3 = int(3 * n);
  std::vector<ArrayRef> arrays = {{f.mean.data(), n3, MPI_DOUBLE},
                                  {f.m2.data(), n3, MPI_DOUBLE},
                                  {f.lumMean.data(), n1, MPI_FLOAT},
                                  {f.lumM2.data(), n1, MPI_FLOAT},
                                  {f.count.data(), n1, MPI_UINT32_T}};
  if (features) {
    arrays.push_back({f.albedoSum.data(), n3, MPI_FLOAT});
    arrays.push_back({f.normalSum.data(), n3, MPI_FLOAT});
    arrays.push_back({f.depthSum.data(), n1, MPI_FLOAT});
  }
  if (halves) {
    arrays.push_back({f.evenSum.data(), n3, MPI_FLOAT});
    arrays.push_back({f.evenCount.data(), n1, MPI_UINT32_T});
    for (std::vector<vec3>* v : {&f.residualMean, &f.residualM2, &f.evenEmissionSum})
      arrays.push_back({v->data(), n3, MPI_FLOAT});
  }
  return arrays;
}

bool AllDone(std::vector<MPI_Request>& requests) {
  if (requests.empty()) return true;
  int done = 0;
  Check(MPI_Testall(int(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE),
        "MPI_Testall");
  return done != 0;
}

}  // namespace

FilmTransferOut::FilmTransferOut(MPI_Comm comm, int dest,
                                 const std::vector<RankReport>& reports, NodeFilms films)
    : films_(std::move(films)), dest_(dest) {
  nlohmann::json header{{"reports", nlohmann::json::array()}, {"nodes", nlohmann::json::array()}};
  for (const RankReport& r : reports) header["reports"].push_back(RankReportToJson(r));
  for (const auto& [node, f] : films_) {
    header["nodes"].push_back({node.begin, node.end, f.width, f.height, !f.albedoSum.empty(),
                               !f.evenSum.empty()});
  }
  header_ = header.dump();
  requests_.emplace_back();
  Check(MPI_Isend(header_.data(), int(header_.size()), MPI_CHAR, dest, kTagReduceHeader, comm,
                  &requests_.back()),
        "MPI_Isend");
  for (auto& [node, f] : films_) {
    for (const ArrayRef& a : Arrays(f, !f.albedoSum.empty(), !f.evenSum.empty(), false)) {
      requests_.emplace_back();
      Check(MPI_Isend(a.data, a.count, a.type, dest, kTagReduceData, comm, &requests_.back()),
            "MPI_Isend");
    }
  }
}

bool FilmTransferOut::Done() { return AllDone(requests_); }

std::unique_ptr<FilmTransferIn> FilmTransferIn::TryStart(MPI_Comm comm, int source,
                                                         FilmPool* pool) {
  std::vector<char> bytes;
  int from = 0;
  if (!TryReceive(comm, source, kTagReduceHeader, &bytes, &from)) return nullptr;
  auto in = std::make_unique<FilmTransferIn>();
  in->source_ = from;
  try {
    nlohmann::json header = nlohmann::json::parse(bytes.begin(), bytes.end());
    for (const auto& r : header.at("reports")) in->reports_.push_back(RankReportFromJson(r));
    for (const auto& n : header.at("nodes")) {
      FilmState f = pool ? pool->Take() : FilmState{};
      f.width = n.at(2).get<uint32_t>();
      f.height = n.at(3).get<uint32_t>();
      ChunkNode node{n.at(0).get<uint32_t>(), n.at(1).get<uint32_t>()};
      in->films_.emplace_back(node, std::move(f));
    }
    size_t i = 0;
    for (const auto& n : header.at("nodes")) {
      FilmState& f = in->films_[i++].second;
      // The arrays follow the header from the same rank, in order (MPI does not reorder).
      for (const ArrayRef& a : Arrays(f, n.at(4).get<bool>(), n.at(5).get<bool>(), true)) {
        in->requests_.emplace_back();
        Check(MPI_Irecv(a.data, a.count, a.type, from, kTagReduceData, comm,
                        &in->requests_.back()),
              "MPI_Irecv");
      }
    }
  } catch (const nlohmann::json::exception& e) {
    throw MpiFailure("malformed film header from rank " + std::to_string(from) + ": " +
                     e.what());
  }
  return in;
}

bool FilmTransferIn::Done() { return AllDone(requests_); }

void FilmTransferIn::Cancel() {
  for (MPI_Request& r : requests_) {
    if (r == MPI_REQUEST_NULL) continue;
    MPI_Cancel(&r);
    MPI_Wait(&r, MPI_STATUS_IGNORE);
  }
  requests_.clear();
  films_.clear();
}

}  // namespace pt::mpi
