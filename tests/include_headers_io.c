/* Proves that tp_io.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror). */
#include "tp_io.h"

int main(void)
{
    return 0;
}
