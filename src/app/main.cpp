// Pipeline: application entry point; everything is in lray_core (app/app.h).
#include "app/app.h"

int main(int argc, char **argv) { return lray::runLray(argc, argv); }
