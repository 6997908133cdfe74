/* Proves that tp_io.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror); each
 * concept header it includes, io/include/tp_io/NAME.h, is compiled alone in a source of its own
 * (tests/CMakeLists.txt writes them). */
#include "tp_io.h"

int main(void)
{
    return 0;
}
