#include "cli_impl.h"
int ea__cli_statics(int argc, char **argv) { (void)argc; (void)argv; return 1; }
int ea__cli_workspace(int argc, char **argv) { (void)argc; (void)argv; return 1; }
int ea__cli_torque_map(int argc, char **argv) { (void)argc; (void)argv; return 1; }
int ea__cli_path(int argc, char **argv) { (void)argc; (void)argv; return 1; }
