# Thin driver around CMake. `make run` and `make test` install missing Debian packages first;
# `make build` only builds.

JOBS := $(shell nproc 2>/dev/null || echo 2)
SCENE := data/lf_elev_220_mt_hood_utm.tif

.PHONY: deps build run test test-sanitize clean

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

clean:
	rm -rf build build-asan
