#include "exit_paths_teardown.h"

#include <stddef.h>

static void (*at_unload)(void);

void exit_paths_teardown_at_unload(void (*teardown)(void)) { at_unload = teardown; }

__attribute__((destructor)) static void unload(void)
{
    if (at_unload) at_unload();
}
