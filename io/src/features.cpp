/* features.cpp - the tp_features set's lifetime (tp_vector.h). */
#include "tp_vector.h"

#include <cstdlib>

extern "C" void tp_features_destroy(tp_features* f)
{
    if (!f)
        return;
    std::free(f->items);
    std::free(f->xy);
    std::free(f->strings);
    std::free(f);
}
