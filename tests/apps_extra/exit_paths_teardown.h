/*
 * exit_paths_teardown.h - a shared library of exit_paths: a toolkit's singleton that owns the GL
 * context and tears it down from the library's destructor, when the program has ended.
 */
#ifndef GLCAST_TEST_EXIT_PATHS_TEARDOWN_H
#define GLCAST_TEST_EXIT_PATHS_TEARDOWN_H

/* `teardown` runs in the library's destructor (at exit, after main and the atexit handlers). */
void exit_paths_teardown_at_unload(void (*teardown)(void));

#endif
