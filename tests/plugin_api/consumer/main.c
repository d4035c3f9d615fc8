/* Built against the installed tree: initialises, checks the version, shuts down. */
#include <firelook/firelook.h>
#include <stdio.h>

int main(void) {
    fl_init_desc desc = fl_init_desc_defaults();
    fl_result r = fl_init(&desc);
    if (r != FL_OK) {
        fprintf(stderr, "fl_init: %s: %s\n", fl_result_string(r), fl_last_error());
        return 1;
    }
    printf("FireLook %u\n", (unsigned)fl_version());
    r = fl_shutdown();
    return r == FL_OK && fl_version() == FIRELOOK_HEADER_VERSION ? 0 : 1;
}
