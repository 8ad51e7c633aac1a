/* Private: temporary files of the atomic outputs (atomic_file.c) and of the
 * figures (figure.c). A temporary of target P is named "P.tmp<pid>.<rest>",
 * so that a later run can tell ours from a live writer's. */
#ifndef EA_AFILE_IMPL_H
#define EA_AFILE_IMPL_H

/** Remove the temporaries of path ("<path>.tmp<pid>.*", regular files owned
 *  by this user) whose process no longer runs: what a killed run (kill -9,
 *  power loss) left behind. Temporaries of live processes are kept. */
void ea__afile_clean_stale(const char *path);

#endif
