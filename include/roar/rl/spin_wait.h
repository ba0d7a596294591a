#pragma once
// Waiting for another thread's next step, which comes within microseconds: spin a little (a sleep and a
// wake-up cost about as much as a state-observation step), then sleep. Shared by the synchronous
// WorkerPool and the asynchronous AsyncVectorEnv.
#include <chrono>
#include <thread>

namespace roar::rl {

// How long a waiting thread spins before it sleeps: a little more than a step's gap.
inline constexpr auto kSpinTime = std::chrono::microseconds(200);

// Tells the core this is a spin loop (frees the pipeline for the sibling thread, saves power).
inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

// Spins until ready() is true or kSpinTime has passed; returns ready().
template <typename Ready>
bool spinFor(const Ready& ready) {
  const auto until = std::chrono::steady_clock::now() + kSpinTime;
  for (unsigned spins = 0; !ready(); ++spins) {
    relax();
    if (spins % 256 == 255 && std::chrono::steady_clock::now() >= until)
      return ready();  // the clock is dearer than a spin
  }
  return true;
}

}  // namespace roar::rl
