# Thin driver around CMake. `make run` and `make test` install missing Debian packages first;
# `make build` only builds.

JOBS := $(shell nproc 2>/dev/null || echo 2)
SCENE := data/lf_elev_220_mt_hood_utm.tif

.PHONY: deps build run test test-sanitize fuzz clean

# tools/deps.sh picks the packages (VTK from libvtk9-dev, or ParaView's own VTK where ParaView is
# installed: the two conflict) and installs the missing ones; one dpkg-query when none is.
# `make deps TP_VTK=system|paraview` forces one VTK; `tools/deps.sh --dry-run` shows the choice.
deps:
	@sh tools/deps.sh

build:
	@[ -f build/CMakeCache.txt ] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
	cmake --build build -j$(JOBS)

# The viewer in a window when there is a display; otherwise one headless frame to a PNG.
run: deps build
	@if [ -n "$$DISPLAY$$WAYLAND_DISPLAY" ]; then \
	    ./build/terrapatch view $(SCENE); \
	else \
	    ./build/terrapatch view --headless --screenshot build/terrapatch-view.png \
	        --stats-json build/terrapatch-view.json $(SCENE) && \
	    echo "run: no display, so the default scene was rendered headless to build/terrapatch-view.png" && \
	    echo "     (statistics in build/terrapatch-view.json; 'terrapatch view --help' for more)"; \
	fi

test: deps build
	ctest --test-dir build --output-on-failure -j$(JOBS)

test-sanitize: deps
	@[ -f build-asan/CMakeCache.txt ] || \
	    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTP_SANITIZE=ON
	cmake --build build-asan -j$(JOBS)
	ctest --test-dir build-asan --output-on-failure -j$(JOBS)

# libFuzzer entry points (tests/fuzz, docs/fuzzing.md), built with clang in build-fuzz/: every
# seed and past finding replayed, then each fuzzer for FUZZ_SECONDS (one at a time). A long run
# of one fuzzer: build-fuzz/fuzz/fuzz_coord_line -runs=1000000 tests/fuzz/corpus/fuzz_coord_line
FUZZ_SECONDS := 20
fuzz:
	@TP_DEPS_FUZZ=1 sh tools/deps.sh
	cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTP_FUZZ=ON \
	    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DTP_BUILD_APP=OFF \
	    -DTP_BUILD_TESTS=OFF -DTP_BUILD_BENCH=OFF -DTP_FUZZ_SECONDS=$(FUZZ_SECONDS)
	cmake --build build-fuzz -j$(JOBS)
	ctest --test-dir build-fuzz --output-on-failure -j$(JOBS) -L fuzz

clean:
	rm -rf build build-asan build-fuzz
