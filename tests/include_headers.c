/* Proves that tp_core.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror). */
#include "tp_core.h"

int main(void)
{
    return 0;
}
