// Pipeline: application entry point; everything is in lray_core (app/app.h).
#include "app/app.h"

#include <csignal>
#include <limits>
#include <malloc.h>

int main(int argc, char **argv) {
  // An output that is a pipe whose reader went away (--stats or an image
  // through a FIFO, a preview client that hung up) is an error with its
  // reason (EPIPE), not a silent death.
  std::signal(SIGPIPE, SIG_IGN);
  // Every frame allocates and frees the same large buffers (its film, the
  // adaptive sample buffer, the image to write). By default glibc hands
  // each one back to the kernel when freed and the next frame faults every
  // page in again: over a quarter of a 20-frame 800 x 600 animation's time. Kept
  // in the process instead (buffers up to 32 MB, the most mallopt allows
  // below mmap; the heap is never trimmed), they are reused as they are.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
  // A new buffer (calloc, util/zeroed_vector.h) is left to the render
  // threads to map, but calloc zeroes, on the calling thread, whatever part
  // of it the heap had already taken from the kernel: by default a pad of
  // 128 KB past each growth, so each of a frame's buffers cost the main
  // thread 32 page faults. Grown by what is asked for alone, nothing is.
  mallopt(M_TOP_PAD, 0);
  return lray::runLray(argc, argv);
}
