/* commands.h - the subcommands of the `largesteps` program, one file each
 * (port/posix/cmd_NAME.c). Each takes the arguments after its name
 * (argv[0] is the command name) and returns the process exit status:
 * 0 success, 1 a failure it reported on stderr, 2 a usage error. */
#ifndef LS_COMMANDS_H
#define LS_COMMANDS_H

int ls_cmd_toy1d(int argc, char **argv);
int ls_cmd_metrics(int argc, char **argv);
int ls_cmd_remesh(int argc, char **argv);
int ls_cmd_render(int argc, char **argv);
int ls_cmd_fit(int argc, char **argv);
int ls_cmd_experiment(int argc, char **argv);
int ls_cmd_tradeoffs(int argc, char **argv);
int ls_cmd_experiment_texture(int argc, char **argv); /* cmd_experiment_texture.c, via experiment */

#endif /* LS_COMMANDS_H */
