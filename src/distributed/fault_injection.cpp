#include "src/distributed/fault_injection.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace pt {
namespace {

// Forwards everything; RenderRange throws once `rangesLeft` is used up.
class FailingSession final : public RenderSession {
 public:
  FailingSession(std::unique_ptr<RenderSession> inner, std::shared_ptr<std::atomic<int>> left)
      : inner_(std::move(inner)), left_(std::move(left)) {}
  RenderResult Render() override { return inner_->Render(); }
  uint64_t RenderRange(uint32_t begin, uint32_t end) override {
    if (left_->fetch_sub(1) <= 0) throw std::runtime_error("injected failure (PT_FAULT_INJECT)");
    return inner_->RenderRange(begin, end);
  }
  uint64_t RenderUpTo(uint32_t spp) override { return inner_->RenderUpTo(spp); }
  void SaveFilmInto(FilmState& film) override { inner_->SaveFilmInto(film); }
  void SnapshotFilm() override { inner_->SnapshotFilm(); }
  void SaveSnapshotInto(FilmState& film) override { inner_->SaveSnapshotInto(film); }
  void LoadFilm(const FilmState& film) override { inner_->LoadFilm(film); }
  void ResetFilm() override { inner_->ResetFilm(); }
  FilmImage Image() override { return inner_->Image(); }
  RenderStats Stats() override { return inner_->Stats(); }
  void SetCamera(const Camera& camera) override { inner_->SetCamera(camera); }
  void SetOptions(const RenderOptions& options) override { inner_->SetOptions(options); }
  void SceneChanged() override { inner_->SceneChanged(); }
  void TopLevelChanged() override { inner_->TopLevelChanged(); }
  void MaterialsChanged() override { inner_->MaterialsChanged(); }

 private:
  std::unique_ptr<RenderSession> inner_;
  std::shared_ptr<std::atomic<int>> left_;
};

}  // namespace

SessionMaker InjectFaults(SessionMaker make, int rank) {
  const char* spec = std::getenv("PT_FAULT_INJECT");
  int target = -1, leaves = 0;
  if (!spec || std::sscanf(spec, "throw:%d:%d", &target, &leaves) != 2 || target != rank)
    return make;
  auto left = std::make_shared<std::atomic<int>>(leaves);
  return [make = std::move(make), left](const Scene& scene, const RenderOptions& options,
                                        const RenderCallbacks& callbacks) {
    return std::unique_ptr<RenderSession>(
        std::make_unique<FailingSession>(make(scene, options, callbacks), left));
  };
}

}  // namespace pt
