// A stage body that can pause between steps (--ray-fetch dynamic): the GPU runs the wide
// traversal stages this way so that a warp lane whose ray has finished takes a new one while
// the other lanes go on, instead of idling until the warp's longest ray ends (Aila and Laine
// 2009, "replacing terminated rays"). Every backend runs the same three bodies:
//
//   struct Task {
//     struct State;                                  // one work item in progress
//     bool Start(State&, uint32_t i) const;          // item i; false: done already (no steps)
//     bool Step(State&) const;                       // one step; true when the item is done
//     void Finish(State&) const;                     // after the last step
//   };
//
// RunTask below runs one item to the end (the CPU, and the GPU's static fetch); the CUDA
// backend's ParallelForDynamic interleaves items per lane.
#pragma once

#include "src/core/pt.h"

namespace pt {

template <typename Task>
PT_HDI void RunTask(const Task& task, uint32_t i) {
  typename Task::State state;
  if (!task.Start(state, i)) return;
  while (!task.Step(state)) {
  }
  task.Finish(state);
}

}  // namespace pt
