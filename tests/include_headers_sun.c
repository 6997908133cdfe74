/* Proves that tp_sun.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror). */
#include "tp_sun.h"

int main(void)
{
    return 0;
}
