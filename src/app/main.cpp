// Pipeline: application entry point; everything is in lray_core (app/app.h).
#include "app/app.h"

#include <csignal>

int main(int argc, char **argv) {
  // An output that is a pipe whose reader went away (--stats or an image
  // through a FIFO, a preview client that hung up) is an error with its
  // reason (EPIPE), not a silent death.
  std::signal(SIGPIPE, SIG_IGN);
  return lray::runLray(argc, argv);
}
