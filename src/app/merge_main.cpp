// Pipeline: application entry point of lray-merge (app/merge.h).
#include "app/merge.h"

int main(int argc, char **argv) { return lray::runMerge(argc, argv); }
