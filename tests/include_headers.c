/* Proves that tp_core.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror); the
 * same target compiles each concept header it includes alone (tests/CMakeLists.txt generates a
 * translation unit per core/include/tp_*.h). */
#include "tp_core.h"

int main(void)
{
    return 0;
}
