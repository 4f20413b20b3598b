/* cascade: the campaign runner (see campaign/README or `cascade --help`). */
#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage: cascade <command> ...\n\nThe campaign runner is being built; see README.md.\n");
        return 0;
    }
    fprintf(stderr, "cascade: the campaign runner is not built yet (see README.md)\n");
    return 2;
}
