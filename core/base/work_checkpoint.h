// A checkpoint (TessellationOptions::checkpoint, which a server throws from when its call is
// cancelled or past its deadline) reached by work done rather than by items: a loop over roots
// calls done() as it goes (tiles, points) and the checkpoint comes every `every` units on that
// thread, so one root with a million tiles does not run unchecked to its end and a thousand small
// roots do not pay for a call each.
#pragma once

#include <cstddef>
#include <functional>

namespace tessera {

class WorkCheckpoint {
 public:
  // `checkpoint` may be empty (nothing is called); it must outlive this.
  WorkCheckpoint(const std::function<void()>& checkpoint, size_t every) : checkpoint_(checkpoint), every_(every) {}

  // `units` more done: the checkpoint once they add up to `every` since the last.
  void done(size_t units = 1) {
    done_ += units;
    if (done_ < every_) return;
    done_ = 0;
    if (checkpoint_) checkpoint_();
  }

 private:
  const std::function<void()>& checkpoint_;
  const size_t every_;
  size_t done_ = 0;
};

}  // namespace tessera
