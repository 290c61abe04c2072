// openpbr-oracle: a line-oriented command-line wrapper around Adobe's reference
// OpenPBR 1.1 BSDF (github.com/adobe/openpbr-bsdf, Apache-2.0), used by Prism's
// tests as an oracle only. It is not part of Prism. See README.md for the protocol.
//
// Build: tools/openpbr-oracle/build.sh [output-path]

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

// Adobe's assertions are routed here instead of aborting the process: a failed
// assertion is counted and reported on stderr after the query's answer.
static int g_assert_count = 0;
static const char* g_assert_message = nullptr;
static void oracle_note_assert(const char* message)
{
    if (g_assert_count++ == 0)
        g_assert_message = message;
}
#define OPENPBR_ASSERT(expr, message)      \
    do                                     \
    {                                      \
        if (!(expr))                       \
            oracle_note_assert(message);   \
    } while (false)
#define OPENPBR_ASSERT_UNREACHABLE(message) oracle_note_assert(message)

// Default settings, spelled out: array LUTs, non-reciprocal (energy-conserving) coat/fuzz.
#define OPENPBR_USE_TEXTURE_LUTS 0
#define OPENPBR_RECIPROCAL_COAT_AND_FUZZ 0
#include "openpbr.h"

namespace {

struct Error : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

float parse_float(const std::string& text, const std::string& what)
{
    char* end = nullptr;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(value))
        throw Error("bad number '" + text + "' for " + what);
    return value;
}

std::uint64_t parse_uint(const std::string& text, const std::string& what)
{
    char* end = nullptr;
    if (text.empty() || text[0] == '-')
        throw Error("bad integer '" + text + "' for " + what);
    const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
    if (*end != '\0')
        throw Error("bad integer '" + text + "' for " + what);
    return value;
}

// "r,g,b" or a single value broadcast to all three channels.
vec3 parse_color(const std::string& text, const std::string& what)
{
    std::vector<std::string> parts;
    std::stringstream stream(text);
    std::string part;
    while (std::getline(stream, part, ','))
        parts.push_back(part);
    if (parts.size() == 1)
        return vec3(parse_float(parts[0], what));
    if (parts.size() != 3)
        throw Error("expected r,g,b for " + what + ", got '" + text + "'");
    return vec3(parse_float(parts[0], what), parse_float(parts[1], what), parse_float(parts[2], what));
}

void set_param(OpenPBR_ResolvedInputs& in, const std::string& name, const std::string& value)
{
    // clang-format off
    struct ScalarParam { const char* name; float OpenPBR_ResolvedInputs::*field; };
    struct ColorParam { const char* name; vec3 OpenPBR_ResolvedInputs::*field; };
    static const ScalarParam scalars[] = {
        {"base_weight", &OpenPBR_ResolvedInputs::base_weight},
        {"base_diffuse_roughness", &OpenPBR_ResolvedInputs::base_diffuse_roughness},
        {"base_metalness", &OpenPBR_ResolvedInputs::base_metalness},
        {"subsurface_weight", &OpenPBR_ResolvedInputs::subsurface_weight},
        {"subsurface_radius", &OpenPBR_ResolvedInputs::subsurface_radius},
        {"subsurface_scatter_anisotropy", &OpenPBR_ResolvedInputs::subsurface_scatter_anisotropy},
        {"specular_weight", &OpenPBR_ResolvedInputs::specular_weight},
        {"specular_roughness", &OpenPBR_ResolvedInputs::specular_roughness},
        {"specular_roughness_anisotropy", &OpenPBR_ResolvedInputs::specular_roughness_anisotropy},
        {"specular_ior", &OpenPBR_ResolvedInputs::specular_ior},
        {"coat_weight", &OpenPBR_ResolvedInputs::coat_weight},
        {"coat_roughness", &OpenPBR_ResolvedInputs::coat_roughness},
        {"coat_roughness_anisotropy", &OpenPBR_ResolvedInputs::coat_roughness_anisotropy},
        {"coat_ior", &OpenPBR_ResolvedInputs::coat_ior},
        {"coat_darkening", &OpenPBR_ResolvedInputs::coat_darkening},
        {"fuzz_weight", &OpenPBR_ResolvedInputs::fuzz_weight},
        {"fuzz_roughness", &OpenPBR_ResolvedInputs::fuzz_roughness},
        {"transmission_weight", &OpenPBR_ResolvedInputs::transmission_weight},
        {"transmission_depth", &OpenPBR_ResolvedInputs::transmission_depth},
        {"transmission_scatter_anisotropy", &OpenPBR_ResolvedInputs::transmission_scatter_anisotropy},
        {"transmission_dispersion_scale", &OpenPBR_ResolvedInputs::transmission_dispersion_scale},
        {"transmission_dispersion_abbe_number", &OpenPBR_ResolvedInputs::transmission_dispersion_abbe_number},
        {"thin_film_weight", &OpenPBR_ResolvedInputs::thin_film_weight},
        {"thin_film_thickness", &OpenPBR_ResolvedInputs::thin_film_thickness},
        {"thin_film_ior", &OpenPBR_ResolvedInputs::thin_film_ior},
        {"emission_luminance", &OpenPBR_ResolvedInputs::emission_luminance},
        {"geometry_opacity", &OpenPBR_ResolvedInputs::geometry_opacity},
    };
    static const ColorParam colors[] = {
        {"base_color", &OpenPBR_ResolvedInputs::base_color},
        {"subsurface_color", &OpenPBR_ResolvedInputs::subsurface_color},
        {"subsurface_radius_scale", &OpenPBR_ResolvedInputs::subsurface_radius_scale},
        {"specular_color", &OpenPBR_ResolvedInputs::specular_color},
        {"coat_color", &OpenPBR_ResolvedInputs::coat_color},
        {"fuzz_color", &OpenPBR_ResolvedInputs::fuzz_color},
        {"transmission_color", &OpenPBR_ResolvedInputs::transmission_color},
        {"transmission_scatter", &OpenPBR_ResolvedInputs::transmission_scatter},
        {"emission_color", &OpenPBR_ResolvedInputs::emission_color},
    };
    // clang-format on
    for (const ScalarParam& p : scalars)
        if (name == p.name)
        {
            in.*p.field = parse_float(value, name);
            return;
        }
    for (const ColorParam& p : colors)
        if (name == p.name)
        {
            in.*p.field = parse_color(value, name);
            return;
        }
    if (name == "geometry_thin_walled")
    {
        if (value != "0" && value != "1")
            throw Error("geometry_thin_walled must be 0 or 1, got '" + value + "'");
        in.geometry_thin_walled = (value == "1");
        return;
    }
    throw Error("unknown parameter '" + name + "'");
}

// Reads "x y z" after a keyword, checks it is (close to) a unit vector, and renormalizes it.
vec3 parse_direction(const std::vector<std::string>& tokens, size_t& pos, const char* keyword)
{
    if (pos >= tokens.size() || tokens[pos] != keyword)
        throw Error(std::string("expected '") + keyword + "'");
    if (pos + 3 >= tokens.size())
        throw Error(std::string("expected 3 numbers after '") + keyword + "'");
    const vec3 v(parse_float(tokens[pos + 1], keyword), parse_float(tokens[pos + 2], keyword), parse_float(tokens[pos + 3], keyword));
    pos += 4;
    const float len = glm::length(v);
    if (std::fabs(len - 1.0f) > 1e-3f)
        throw Error(std::string(keyword) + " is not a unit vector (length " + std::to_string(len) + ")");
    return v / len;
}

// splitmix64: small, deterministic, good enough for Monte Carlo estimates here.
struct Rng
{
    std::uint64_t state;
    float next()  // uniform in [0, 1), as Adobe's sampler requires
    {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return float(z >> 40) * 0x1.0p-24f;
    }
};

std::string fmt(double v)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.9g", v);
    return buffer;
}

std::string answer(const std::string& line)
{
    std::vector<std::string> tokens;
    std::istringstream stream(line);
    for (std::string token; stream >> token;)
        tokens.push_back(token);
    if (tokens.empty())
        throw Error("empty line");
    const std::string& command = tokens[0];
    if (command != "eval" && command != "albedo" && command != "sample")
        throw Error("unknown command '" + command + "' (expected eval, albedo or sample)");

    OpenPBR_ResolvedInputs inputs = openpbr_make_default_resolved_inputs();  // spec defaults, z-up frame, tangent +x
    size_t pos = 1;
    for (; pos < tokens.size() && tokens[pos] != "wo"; ++pos)
    {
        const size_t eq = tokens[pos].find('=');
        if (eq == std::string::npos)
            throw Error("expected name=value, got '" + tokens[pos] + "'");
        set_param(inputs, tokens[pos].substr(0, eq), tokens[pos].substr(eq + 1));
    }
    const vec3 wo = parse_direction(tokens, pos, "wo");
    if (wo.z == 0.0f)
        throw Error("wo is exactly tangent to the surface");

    const OpenPBR_PreparedBsdf prepared = openpbr_prepare(inputs, vec3(1.0f), OpenPBR_BaseRgbWavelengths_nm, OpenPBR_VacuumIor, wo);

    std::string result;
    if (command == "eval")
    {
        const vec3 wi = parse_direction(tokens, pos, "wi");
        if (pos != tokens.size())
            throw Error("trailing tokens after wi");
        // Adobe's openpbr_eval returns f * |cos(theta_i)|; divide the cosine back out.
        const vec3 f_cos = openpbr_get_sum_of_diffuse_specular(openpbr_eval(prepared, wi));
        const float cos_i = std::fabs(wi.z);
        const vec3 f = cos_i > 0.0f ? f_cos / cos_i : vec3(0.0f);
        const float pdf = openpbr_pdf(prepared, wi);
        result = fmt(f.x) + " " + fmt(f.y) + " " + fmt(f.z) + " " + fmt(pdf);
    }
    else if (command == "albedo")
    {
        if (pos + 4 != tokens.size() || tokens[pos] != "n" || tokens[pos + 2] != "seed")
            throw Error("expected 'n N seed S' after wo");
        const std::uint64_t n = parse_uint(tokens[pos + 1], "n");
        if (n == 0 || n > 100000000ull)
            throw Error("n must be in 1..100000000");
        Rng rng{parse_uint(tokens[pos + 3], "seed")};
        double sum[3] = {0.0, 0.0, 0.0};
        for (std::uint64_t i = 0; i < n; ++i)
        {
            const float u0 = rng.next();  // drawn on separate lines: argument order is unspecified
            const float u1 = rng.next();
            const float u2 = rng.next();
            vec3 wi;
            OpenPBR_DiffuseSpecular weight;
            float pdf;
            OpenPBR_BsdfLobeType lobe_type;
            openpbr_sample(prepared, vec3(u0, u1, u2), wi, weight, pdf, lobe_type);
            if (!(pdf > 0.0f))
                continue;  // failed sample contributes zero
            const vec3 w = openpbr_get_sum_of_diffuse_specular(weight);  // = f |cos| / pdf
            for (int c = 0; c < 3; ++c)
                sum[c] += std::isfinite(w[c]) ? w[c] : 0.0;
        }
        result = fmt(sum[0] / double(n)) + " " + fmt(sum[1] / double(n)) + " " + fmt(sum[2] / double(n));
    }
    else  // sample (debug aid): "sample <params> wo x y z u u0 u1 u2"
    {
        if (pos + 4 != tokens.size() || tokens[pos] != "u")
            throw Error("expected 'u u0 u1 u2' after wo");
        vec3 u;
        for (int k = 0; k < 3; ++k)
        {
            u[k] = parse_float(tokens[pos + 1 + k], "u");
            if (u[k] < 0.0f || u[k] >= 1.0f)
                throw Error("u values must be in [0, 1)");
        }
        vec3 wi(0.0f);
        OpenPBR_DiffuseSpecular weight = openpbr_make_zero_diffuse_specular();
        float pdf = 0.0f;
        OpenPBR_BsdfLobeType lobe_type = 0;
        openpbr_sample(prepared, u, wi, weight, pdf, lobe_type);
        if (!(pdf > 0.0f))
            return "none";
        const vec3 w = openpbr_get_sum_of_diffuse_specular(weight);
        result = fmt(wi.x) + " " + fmt(wi.y) + " " + fmt(wi.z) + " " + fmt(w.x) + " " + fmt(w.y) + " " + fmt(w.z) + " " + fmt(pdf) + " " +
                 std::to_string(lobe_type);
    }
    return result;
}

}  // namespace

int main()
{
    std::ios::sync_with_stdio(false);
    std::string line;
    for (long line_number = 1; std::getline(std::cin, line); ++line_number)
    {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        g_assert_count = 0;
        try
        {
            std::cout << answer(line) << '\n';
        }
        catch (const std::exception& e)
        {
            std::cout << "error " << e.what() << '\n';
        }
        std::cout.flush();  // one answer per query, immediately, so callers can stream
        if (g_assert_count > 0)
            std::cerr << "openpbr-oracle: line " << line_number << ": " << g_assert_count << " Adobe assertion(s) failed, first: "
                      << g_assert_message << '\n';
    }
    return 0;
}
