// Pipeline: application entry point of lray-compare (compare/compare_tool.h).
#include "compare/compare_tool.h"

int main(int argc, char **argv) { return lray::compare::runCompare(argc, argv); }
