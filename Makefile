# Thin driver around CMake. `make run` and `make test` install missing Debian packages first;
# `make build` only builds.

DEBS := cmake pkg-config gcc g++ libgdal-dev libproj-dev libgeographiclib-dev libopenimageio-dev libvtk9-dev \
        libglfw3-dev libepoxy-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libstb-dev \
        gnuplot-nox xvfb xdotool
JOBS := $(shell nproc 2>/dev/null || echo 2)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
SCENE := data/lf_elev_220_mt_hood_utm.tif

.PHONY: deps build run test test-sanitize clean

# One dpkg-query for all packages; apt runs only when something is missing. `env` because
# sudo drops DEBIAN_FRONTEND from the environment.
deps:
	@installed=" $$(dpkg-query -W -f='$${db:Status-Abbrev} $${Package}\n' $(DEBS) 2>/dev/null \
	    | awk '$$1 == "ii" { print $$2 }' | tr '\n' ' ') "; \
	missing=; \
	for p in $(DEBS); do \
	    case "$$installed" in *" $$p "*) ;; *) missing="$$missing $$p" ;; esac; \
	done; \
	if [ -n "$$missing" ]; then \
	    echo "deps: installing$$missing"; \
	    $(SUDO) apt-get update -qq && \
	    $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing; \
	fi

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
