// Casts the rays of a Prism dump with native Embree 3 and times it the way `prism
// bench` times Prism: the same triangles, the same primary and shadow rays, the same
// number of threads, each pass repeated until a minimum time has passed.
//
// Usage: harness DUMP_DIR [--threads T] [--seconds S] [--builds K] [--config C]
//        harness --probe [--config C]
//
// --config adds to Embree's device configuration (`isa=avx2` to hold it to AVX2);
// --probe prints Embree's own description of the device (its ISA) and exits.
//
// DUMP_DIR is what `prism bench SCENE CAMERA --dump DIR` writes (src/bench.rs,
// `write_bench_dump`). Prints one JSON object:
//   build_s            median over K builds (rtcNewScene .. rtcCommitScene, medium
//                      quality: what rtcCommitScene does by default), T build threads;
//                      build_first_s is the first, which also pays for the first
//                      touch of its memory as `prism bench`'s single build does
//   intersect1_mrays   rtcIntersect1, closest hit, primary rays
//   occluded1_mrays    rtcOccluded1, shadow rays
//   intersect16_mrays  rtcIntersect16, coherent context flag, primary rays in packets
//                      of 16: one 4x4 pixel tile a packet (edge tiles have idle lanes)
//   scene_bytes        what Embree's memory monitor counts for the last built scene:
//                      its BVH and its triangle leaves (the application's vertex and
//                      index buffers, shared with Embree, are not among them)
// and how Embree's answers differ from Prism's (hits.bin, occluded.u8).
//
// Rays are handed to T std::threads in chunks of 4096 taken from a shared counter, so
// a thread that finishes early takes more, as rayon does for Prism. Each thread sets
// flush-to-zero and denormals-are-zero, as Embree asks of the threads that call it.
//
// Build: g++ -O3 -std=c++17 -pthread harness.cpp -lembree3 (benches/embree3.sh does).

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

[[noreturn]] void fail(const std::string& message) {
    std::fprintf(stderr, "harness: %s\n", message.c_str());
    std::exit(1);
}

std::vector<char> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read " + path);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
}

template <typename T>
std::vector<T> read_array(const std::string& path, size_t per_item, size_t items) {
    std::vector<char> bytes = read_file(path);
    if (bytes.size() != items * per_item * sizeof(T)) {
        fail(path + " has " + std::to_string(bytes.size()) + " bytes, meta.json says " +
             std::to_string(items) + " items of " + std::to_string(per_item * sizeof(T)));
    }
    std::vector<T> out(items * per_item);
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

// A non-negative integer field of meta.json, which Prism writes flat and on one line.
long long meta_field(const std::string& json, const std::string& key) {
    size_t at = json.find("\"" + key + "\":");
    if (at == std::string::npos) fail("meta.json has no " + key);
    return std::atoll(json.c_str() + at + key.size() + 3);
}

struct Dump {
    long long width, height;
    size_t triangles, rays, shadow_rays;
    std::vector<float> vertices;  // 9 a triangle, then padding (see load)
    std::vector<float> rays_f;    // origin, direction
    std::vector<float> shadow_f;  // origin, direction, end of segment
    std::vector<int32_t> prism_prim;
    std::vector<float> prism_t;
    std::vector<uint8_t> prism_occluded;
};

Dump load(const std::string& dir) {
    std::vector<char> meta_bytes = read_file(dir + "/meta.json");
    std::string meta(meta_bytes.begin(), meta_bytes.end());
    Dump d;
    d.width = meta_field(meta, "width");
    d.height = meta_field(meta, "height");
    d.triangles = meta_field(meta, "triangles");
    d.rays = meta_field(meta, "rays");
    d.shadow_rays = meta_field(meta, "shadow_rays");
    d.vertices = read_array<float>(dir + "/triangles.f32", 9, d.triangles);
    // Embree reads each float3 vertex with one 16-byte load: the last one needs 4
    // readable bytes after it.
    d.vertices.push_back(0.0f);
    d.rays_f = read_array<float>(dir + "/rays.f32", 6, d.rays);
    d.shadow_f = read_array<float>(dir + "/shadow.f32", 7, d.shadow_rays);
    std::vector<char> hits = read_file(dir + "/hits.bin");
    if (hits.size() != d.rays * 8) fail("hits.bin does not have 8 bytes a ray");
    d.prism_prim.resize(d.rays);
    d.prism_t.resize(d.rays);
    for (size_t i = 0; i < d.rays; ++i) {
        std::memcpy(&d.prism_prim[i], &hits[i * 8], 4);
        std::memcpy(&d.prism_t[i], &hits[i * 8 + 4], 4);
    }
    d.prism_occluded = read_array<uint8_t>(dir + "/occluded.u8", 1, d.shadow_rays);
    return d;
}

// Bytes Embree holds, as its memory monitor reports them (allocations positive, frees
// negative).
std::atomic<long long> embree_bytes{0};

bool on_memory(void*, ssize_t bytes, bool) {
    embree_bytes += bytes;
    return true;
}

void on_error(void*, RTCError code, const char* message) {
    fail("embree error " + std::to_string(code) + ": " + (message ? message : ""));
}

RTCScene build_scene(RTCDevice device, const Dump& d, const std::vector<uint32_t>& index) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               d.vertices.data(), 0, 3 * sizeof(float), 3 * d.triangles);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, index.data(),
                               0, 3 * sizeof(uint32_t), d.triangles);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
}

struct Rate {
    double mrays;
    int passes;
};

// Runs `work(begin, end)` over [0, items) on `threads` threads, chunk by chunk, pass
// after pass until `seconds` have passed (at least one pass).
template <typename Work>
Rate repeat_for(double seconds, int threads, size_t items, size_t chunk, size_t rays_per_pass,
                Work work) {
    auto start = Clock::now();
    int passes = 0;
    double elapsed = 0.0;
    do {
        std::atomic<size_t> next{0};
        auto worker = [&] {
            _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
            _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
            for (;;) {
                size_t begin = next.fetch_add(chunk);
                if (begin >= items) return;
                work(begin, std::min(items, begin + chunk));
            }
        };
        std::vector<std::thread> pool;
        for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (auto& t : pool) t.join();
        ++passes;
        elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    } while (elapsed < seconds);
    return {passes * double(rays_per_pass) / elapsed / 1e6, passes};
}

// Packets of 16 primary rays: 4x4 pixel tiles, tile rows top to bottom, lanes row by
// row within a tile, -1 for the lanes of edge tiles outside the image. Without an
// image size, 16 consecutive rays.
std::vector<int64_t> packet_lanes(const Dump& d, bool tiles) {
    std::vector<int64_t> lanes;
    if (!tiles) {
        for (size_t i = 0; i < (d.rays + 15) / 16 * 16; ++i)
            lanes.push_back(i < d.rays ? int64_t(i) : -1);
        return lanes;
    }
    for (long long ty = 0; ty < d.height; ty += 4)
        for (long long tx = 0; tx < d.width; tx += 4)
            for (long long y = ty; y < ty + 4; ++y)
                for (long long x = tx; x < tx + 4; ++x)
                    lanes.push_back(x < d.width && y < d.height ? y * d.width + x : -1);
    return lanes;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        fail("usage: harness DUMP_DIR [--threads T] [--seconds S] [--builds K] [--config C]");
    }
    std::string dir = argv[1];
    bool probe = dir == "--probe";
    int threads = int(std::max(1u, std::thread::hardware_concurrency()));
    double seconds = 1.0;
    int builds = 7;
    std::string extra_config;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string flag = argv[i];
        if (flag == "--threads") threads = std::atoi(argv[i + 1]);
        else if (flag == "--seconds") seconds = std::atof(argv[i + 1]);
        else if (flag == "--builds") builds = std::atoi(argv[i + 1]);
        else if (flag == "--config") extra_config = argv[i + 1];
        else fail("unknown option " + flag);
    }
    if (threads < 1 || builds < 1 || !(seconds >= 0.0)) fail("bad --threads, --seconds or --builds");
    if (probe) {
        RTCDevice device = rtcNewDevice(("verbose=1," + extra_config).c_str());
        if (!device) fail("rtcNewDevice failed");
        rtcReleaseDevice(device);
        return 0;
    }

    Dump d = load(dir);
    std::vector<uint32_t> index(3 * d.triangles);
    for (size_t i = 0; i < index.size(); ++i) index[i] = uint32_t(i);

    // Embree's build threads are its own tasking system's: limit them to T as well.
    std::string config = "threads=" + std::to_string(threads);
    if (!extra_config.empty()) config += "," + extra_config;
    RTCDevice device = rtcNewDevice(config.c_str());
    if (!device) fail("rtcNewDevice failed: " + std::to_string(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(device, on_error, nullptr);
    rtcSetDeviceMemoryMonitorFunction(device, on_memory, nullptr);

    std::vector<double> build_times;
    RTCScene scene = nullptr;
    long long scene_bytes = 0;
    for (int b = 0; b < builds; ++b) {
        if (scene) rtcReleaseScene(scene);
        long long before = embree_bytes;
        auto start = Clock::now();
        scene = build_scene(device, d, index);
        scene_bytes = embree_bytes - before;
        build_times.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    std::vector<double> sorted_builds = build_times;
    std::sort(sorted_builds.begin(), sorted_builds.end());
    double build_s = sorted_builds[sorted_builds.size() / 2];

    const size_t chunk = 4096;
    std::vector<uint32_t> prim1(d.rays);
    std::vector<float> t1(d.rays);
    Rate intersect1 = repeat_for(seconds, threads, d.rays, chunk, d.rays, [&](size_t b, size_t e) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (size_t i = b; i < e; ++i) {
            const float* r = &d.rays_f[i * 6];
            RTCRayHit rh;
            rh.ray.org_x = r[0], rh.ray.org_y = r[1], rh.ray.org_z = r[2];
            rh.ray.dir_x = r[3], rh.ray.dir_y = r[4], rh.ray.dir_z = r[5];
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = ~0u;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            prim1[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID
                                                                : rh.hit.primID;
            t1[i] = rh.ray.tfar;
        }
    });

    std::vector<uint8_t> occluded(d.shadow_rays);
    Rate occluded1 =
        repeat_for(seconds, threads, d.shadow_rays, chunk, d.shadow_rays, [&](size_t b, size_t e) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (size_t i = b; i < e; ++i) {
                const float* r = &d.shadow_f[i * 7];
                RTCRay ray;
                ray.org_x = r[0], ray.org_y = r[1], ray.org_z = r[2];
                ray.dir_x = r[3], ray.dir_y = r[4], ray.dir_z = r[5];
                ray.tnear = 0.0f;
                ray.tfar = r[6];
                ray.time = 0.0f;
                ray.mask = ~0u;
                ray.id = 0;
                ray.flags = 0;
                rtcOccluded1(scene, &ctx, &ray);
                // Embree marks a blocked ray by setting its tfar to -inf.
                occluded[i] = ray.tfar < 0.0f;
            }
        });

    bool tiles = d.width > 0 && d.height > 0 && size_t(d.width * d.height) == d.rays;
    std::vector<int64_t> lanes = packet_lanes(d, tiles);
    size_t packets = lanes.size() / 16;
    std::vector<uint32_t> prim16(d.rays);
    std::vector<float> t16(d.rays);
    Rate intersect16 = repeat_for(seconds, threads, packets, chunk / 16, d.rays, [&](size_t b, size_t e) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        RTCRayHit16 rh;
        alignas(64) int valid[16];
        for (size_t p = b; p < e; ++p) {
            const int64_t* lane = &lanes[p * 16];
            for (int k = 0; k < 16; ++k) {
                valid[k] = lane[k] >= 0 ? -1 : 0;
                const float* r = &d.rays_f[size_t(std::max<int64_t>(lane[k], 0)) * 6];
                rh.ray.org_x[k] = r[0], rh.ray.org_y[k] = r[1], rh.ray.org_z[k] = r[2];
                rh.ray.dir_x[k] = r[3], rh.ray.dir_y[k] = r[4], rh.ray.dir_z[k] = r[5];
                rh.ray.tnear[k] = 0.0f;
                rh.ray.tfar[k] = INFINITY;
                rh.ray.time[k] = 0.0f;
                rh.ray.mask[k] = ~0u;
                rh.ray.id[k] = 0;
                rh.ray.flags[k] = 0;
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene, &ctx, &rh);
            for (int k = 0; k < 16; ++k) {
                if (lane[k] < 0) continue;
                prim16[lane[k]] = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID
                                      ? RTC_INVALID_GEOMETRY_ID
                                      : rh.hit.primID[k];
                t16[lane[k]] = rh.ray.tfar[k];
            }
        }
    });

    // Agreement with Prism, counted as benches/embree.py counts it: a ray disagrees when
    // one hits and the other misses, or both hit different triangles at distances more
    // than 1e-4 apart (relative); a different triangle at the same distance is a shared
    // edge.
    size_t hits = 0, hit_or_miss = 0, other_triangle = 0, distance = 0, disagree = 0;
    size_t packet_differs = 0;
    for (size_t i = 0; i < d.rays; ++i) {
        bool e_hit = prim1[i] != RTC_INVALID_GEOMETRY_ID;
        bool p_hit = d.prism_prim[i] >= 0;
        hits += e_hit;
        bool other = false, far = false;
        if (e_hit != p_hit) {
            ++hit_or_miss;
        } else if (e_hit) {
            other = prim1[i] != uint32_t(d.prism_prim[i]);
            far = std::fabs(t1[i] - d.prism_t[i]) / std::max(std::fabs(t1[i]), 1e-30f) > 1e-4f;
            other_triangle += other;
            distance += far;
        }
        disagree += (e_hit != p_hit) || (other && far);
        packet_differs += prim16[i] != prim1[i] || t16[i] != t1[i];
    }
    size_t blocked = 0, occluded_differs = 0;
    for (size_t i = 0; i < d.shadow_rays; ++i) {
        blocked += occluded[i];
        occluded_differs += occluded[i] != (d.prism_occluded[i] != 0);
    }

    int version = int(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION));
    const char* tasking[] = {"internal", "tbb", "ppl"};
    long tasking_system = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_TASKING_SYSTEM);
    std::printf(
        "{\"embree_version\":\"%d.%d.%d\",\"config\":\"%s\",\"tasking\":\"%s\",\"native_ray16\":%s,"
        "\"threads\":%d,\"triangles\":%zu,\"rays\":%zu,\"shadow_rays\":%zu,"
        "\"builds\":%d,\"build_s\":%.6f,\"build_min_s\":%.6f,\"build_first_s\":%.6f,"
        "\"scene_bytes\":%lld,"
        "\"intersect1_mrays\":%.4f,\"intersect1_passes\":%d,"
        "\"occluded1_mrays\":%.4f,\"occluded1_passes\":%d,"
        "\"intersect16_mrays\":%.4f,\"intersect16_passes\":%d,\"packets\":\"%s\","
        "\"hit_fraction\":%.6f,\"hit_or_miss_differs\":%zu,\"other_triangle\":%zu,"
        "\"distance_differs\":%zu,\"disagree\":%zu,\"disagree_fraction\":%.3g,"
        "\"intersect16_differs_from_intersect1\":%zu,"
        "\"occluded_fraction\":%.6f,\"occluded_differs\":%zu}\n",
        version / 10000, version / 100 % 100, version % 100, config.c_str(),
        tasking_system >= 0 && tasking_system < 3 ? tasking[tasking_system] : "?",
        rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) ? "true" : "false",
        threads, d.triangles, d.rays, d.shadow_rays, builds, build_s, sorted_builds.front(),
        build_times.front(), scene_bytes,
        intersect1.mrays, intersect1.passes, occluded1.mrays, occluded1.passes,
        intersect16.mrays, intersect16.passes, tiles ? "4x4 tiles" : "16 consecutive rays",
        double(hits) / std::max<size_t>(d.rays, 1), hit_or_miss, other_triangle, distance,
        disagree, double(disagree) / std::max<size_t>(d.rays, 1), packet_differs,
        double(blocked) / std::max<size_t>(d.shadow_rays, 1), occluded_differs);

    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
