#include "raplas/app/cli.hpp"

int main(int argc, char** argv) { return raplas::run_cli(argc, argv); }
