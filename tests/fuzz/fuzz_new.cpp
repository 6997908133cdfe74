/*
 * fuzz_new.cpp - operator new and delete for the fuzzers, over malloc and free (which
 * AddressSanitizer still checks), with two changes:
 *
 * 1. An allocation beyond kLimit throws std::bad_alloc. A file header can claim any size
 *    (VTK's XML reader allocates the 1 TiB a block header asks for, in
 *    vtkXMLDataParser::ReadBlock). On a real machine that `new` throws std::bad_alloc, which
 *    our readers catch and report; under ASan `new` aborts the process instead ("allocator is
 *    out of memory"), which would stop each fuzzer at the first such header.
 * 2. Arrays (new[]) of kBig bytes or more come from mmap, unchecked by ASan. OpenImageIO
 *    2.4's ImageInput::read_scanlines asks for a 64 MB scratch buffer (new char[]) for any
 *    image, even 16 x 16; ASan's shadow for it took 0.4 s an input (4 inputs a second). Only
 *    those library buffers are that big: the fuzzers skip rasters over 256 x 256. Plain
 *    `new` (objects, std::vector) stays ASan's: LeakSanitizer does not look for pointers in
 *    mmap'd blocks, so libFuzzer's own big vectors must not be there.
 */
#include <sys/mman.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>

namespace {
constexpr std::size_t kLimit = std::size_t(1) << 31; /* 2 GiB, libFuzzer's -rss_limit_mb */
constexpr std::size_t kBig = std::size_t(16) << 20;

/* The mmap'd blocks now live; few at a time (one scratch buffer per read). */
struct Mapped {
    void* p;
    std::size_t size;
};
Mapped g_mapped[64];
std::mutex g_lock;

void* try_allocate(std::size_t size, bool array)
{
    if (size > kLimit)
        return nullptr;
    if (!array || size < kBig)
        return std::malloc(size ? size : 1);
    std::lock_guard<std::mutex> hold(g_lock);
    for (Mapped& m : g_mapped) {
        if (m.p)
            continue;
        void* p = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED)
            return nullptr;
        m = {p, size};
        return p;
    }
    return std::malloc(size); /* table full: ASan's own, slow but right */
}

void release(void* p)
{
    if (!p)
        return;
    {
        std::lock_guard<std::mutex> hold(g_lock);
        for (Mapped& m : g_mapped)
            if (m.p == p) {
                munmap(m.p, m.size);
                m = {nullptr, 0};
                return;
            }
    }
    std::free(p);
}

void* allocate(std::size_t size, bool array)
{
    void* p = try_allocate(size, array);
    if (!p)
        throw std::bad_alloc();
    return p;
}
} // namespace

void* operator new(std::size_t size)
{
    return allocate(size, false);
}
void* operator new[](std::size_t size)
{
    return allocate(size, true);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
    return try_allocate(size, false);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
    return try_allocate(size, true);
}
void operator delete(void* p) noexcept
{
    release(p);
}
void operator delete[](void* p) noexcept
{
    release(p);
}
void operator delete(void* p, std::size_t) noexcept
{
    release(p);
}
void operator delete[](void* p, std::size_t) noexcept
{
    release(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept
{
    release(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept
{
    release(p);
}
