/* Proves that tp_geo.h is valid C11 on its own (compiled with -std=c11 -pedantic -Werror). */
#include "tp_geo.h"

int main(void)
{
    return 0;
}
