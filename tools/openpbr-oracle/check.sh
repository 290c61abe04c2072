#!/bin/sh
# Sanity checks of the OpenPBR oracle (and of our reading of Adobe's conventions).
# Usage: tools/openpbr-oracle/check.sh [oracle-binary]
# Without an argument it builds a temporary binary with build.sh (exit 3 = prerequisite missing).
# Prints one line per check with the measured numbers; exits 1 if any check fails.
set -u
here=$(cd "$(dirname "$0")" && pwd)
if [ $# -ge 1 ]; then
    oracle=$1
else
    oracle=${TMPDIR:-/tmp}/openpbr-oracle-check.$$
    "$here/build.sh" "$oracle" || exit $?
    trap 'rm -f "$oracle"' EXIT
fi
failures=0
PI=3.14159265358979

# report NAME OK(0|1) DETAILS
report() {
    if [ "$2" = 1 ]; then echo "ok    $1: $3"; else echo "FAIL  $1: $3"; failures=$((failures + 1)); fi
}

# expect NAME QUERY EXPECTED TOLERANCE: every answer field within TOLERANCE of EXPECTED ('-' skips a field).
expect() {
    got=$(printf '%s\n' "$2" | "$oracle")
    ok=$(printf '%s\n%s\n' "$got" "$3" | awk -v tol="$4" 'NR==1{n=split($0,g)} NR==2{m=split($0,e)}
        END{ok=(n==m); for(i=1;i<=m&&ok;i++) if(e[i]!="-"){d=g[i]-e[i]; if(d<0)d=-d; if(!(d<=tol)) ok=0}; print ok}')
    report "$1" "$ok" "got [$got] expected [$3] +-$4"
}

# EON (energy-preserving Oren-Nayar, OpenPBR 1.1) value for rho=1 with Adobe's approximate FON albedo.
eon() { # wo_x wo_y wo_z wi_x wi_y wi_z roughness
    awk -v ox="$1" -v oy="$2" -v oz="$3" -v ix="$4" -v iy="$5" -v iz="$6" -v r="$7" -v pi="$PI" '
    function efon(mu,   c) { c = 1 - mu
        return (1 + r * c * (0.0571085289 + c * (0.491881867 + c * (-0.332181442 + c * 0.0714429953)))) / (1 + A * r) }
    BEGIN { A = 0.5 - 2 / (3 * pi); B = 2 / 3 - 28 / (15 * pi)
        s = ox * ix + oy * iy + oz * iz - oz * iz; t = oz > iz ? oz : iz; st = s > 0 ? s / t : s
        AF = 1 / (1 + A * r); fss = AF * (1 + r * st) / pi; avg = AF * (1 + B * r)
        fms = (1 - efon(oz)) * (1 - efon(iz)) / (1 - avg) / pi   # rho_ms = 1 for rho = 1
        f = fss + fms; printf "%.9g %.9g %.9g %.9g\n", f, f, f, iz / pi }'
}

# integrate PARAMS WO N SEED: uniform-sphere Monte Carlo of eval -> "mean(f|cos|)*4pi mean(pdf)*4pi"
integrate() {
    awk -v p="$1" -v wo="$2" -v n="$3" -v seed="$4" 'BEGIN { srand(seed)
        for (k = 0; k < n; k++) { z = 2 * rand() - 1; a = 6.28318530717959 * rand(); r = sqrt(1 - z * z)
            printf "eval %s wo %s wi %.9f %.9f %.9f\n", p, wo, r * cos(a), r * sin(a), z } }' > "$oracle.q"
    "$oracle" < "$oracle.q" | paste -d' ' "$oracle.q" - | awk -v pi="$PI" '{ z = $(NF-4); if (z < 0) z = -z
        s += $(NF-3) * z; q += $NF; n++ } END { printf "%.5f %.5f\n", 4 * pi * s / n, 4 * pi * q / n }'
    rm -f "$oracle.q"
}

# within A B TOL -> 1 if |A-B| <= TOL
within() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; print (d <= t) ? 1 : 0 }'; }

LAMBERT="base_color=1,1,1 specular_weight=0"
METAL="base_metalness=1 base_color=1,1,1 specular_roughness=0.5"
GLASS="transmission_weight=1 specular_roughness=0.3"
IP=$(awk -v pi="$PI" 'BEGIN { printf "%.9g", 1 / pi }')

echo "== conventions"
expect "lambert f=1/pi, pdf=cos/pi (normal)" "eval $LAMBERT wo 0 0 1 wi 0 0 1" "$IP $IP $IP $IP" 1e-6
expect "lambert f=1/pi, pdf=cos/pi (oblique)" "eval $LAMBERT wo 0.6 0 0.8 wi -0.48 0.6 0.64" \
    "$IP $IP $IP $(awk -v pi="$PI" 'BEGIN { printf "%.9g", 0.64 / pi }')" 1e-6
expect "lambert wi below surface -> 0" "eval $LAMBERT wo 0.6 0 0.8 wi 0 0.6 -0.8" "0 0 0 0" 0
expect "lambert back face is two-sided" "eval $LAMBERT wo 0.6 0 -0.8 wi 0 0 -1" "$IP $IP $IP $IP" 1e-6
expect "EON base_diffuse_roughness=1 (s<0)" "eval $LAMBERT base_diffuse_roughness=1 wo 0.6 0 0.8 wi -0.48 0.6 0.64" \
    "$(eon 0.6 0 0.8 -0.48 0.6 0.64 1)" 1e-5
expect "EON base_diffuse_roughness=1 (s>0)" "eval $LAMBERT base_diffuse_roughness=1 wo 0.6 0 0.8 wi 0.48 0.6 0.64" \
    "$(eon 0.6 0 0.8 0.48 0.6 0.64 1)" 1e-5
expect "smooth metal off-peak eval ~ 0 (no delta lobes)" \
    "eval base_metalness=1 base_color=1,1,1 specular_roughness=0 wo 0.6 0 0.8 wi -0.48 0.6 0.64" "0 0 0 0" 1e-9

echo "== sample/pdf/eval consistency (sample: wi, weight, pdf; then eval at wi)"
for m in "" "$METAL" "$GLASS" "fuzz_weight=1 coat_weight=1 base_color=0.2,0.5,0.8" "thin_film_weight=1 specular_roughness=0.2"; do
    for u in "0.1 0.2 0.3" "0.5 0.7 0.9" "0.95 0.4 0.6"; do
        s=$(printf 'sample %s wo 0.6 0 0.8 u %s\n' "$m" "$u" | "$oracle")
        [ "$s" = none ] && continue
        set -- $s
        e=$(printf 'eval %s wo 0.6 0 0.8 wi %s %s %s\n' "$m" "$1" "$2" "$3" | "$oracle")
        ok=$(printf '%s %s\n' "$s" "$e" | awk '{ c = $3 < 0 ? -$3 : $3; pdf = $7; w = $4; f = $9; p2 = $12
            ok = (p2 - pdf <= 1e-4 * pdf && pdf - p2 <= 1e-4 * pdf) && ((w - f * c / pdf) ^ 2 <= (1e-4 * w) ^ 2); print ok }')
        report "[$m] u=$u" "$ok" "sample [$s] eval [$e]"
    done
done

echo "== albedo (importance sampling, n=200000)"
A="n 200000 seed 1"
expect "lambert white, normal" "albedo $LAMBERT wo 0 0 1 $A" "1 1 1" 2e-3
expect "lambert white, 60deg" "albedo $LAMBERT wo 0.866025404 0 0.5 $A" "1 1 1" 2e-3
expect "EON white roughness=1, normal" "albedo $LAMBERT base_diffuse_roughness=1 wo 0 0 1 $A" "1 1 1" 5e-3
expect "rough white metal, normal" "albedo $METAL wo 0 0 1 $A" "1 1 1" 5e-3
expect "rough white metal, 60deg" "albedo $METAL wo 0.866025404 0 0.5 $A" "1 1 1" 5e-3
expect "smooth white metal, 37deg" "albedo base_metalness=1 base_color=1,1,1 specular_roughness=0 wo 0.6 0 0.8 $A" "1 1 1" 1e-3
expect "default material, normal (0.04+0.96*0.8)" "albedo wo 0 0 1 $A" "0.808 0.808 0.808" 3e-3
expect "clear rough glass, normal" "albedo $GLASS wo 0 0 1 $A" "1 1 1" 5e-3
expect "clear rough glass, 60deg" "albedo $GLASS wo 0.866025404 0 0.5 $A" "1 1 1" 5e-3
expect "clear rough glass, from inside" "albedo $GLASS wo 0.6 0 -0.8 $A" "1 1 1" 5e-3
expect "clear smooth glass, 37deg" "albedo transmission_weight=1 specular_roughness=0 wo 0.6 0 0.8 $A" "1 1 1" 1e-3
expect "fuzz over white lambert" "albedo $LAMBERT fuzz_weight=1 wo 0.6 0 0.8 $A" "1 1 1" 2e-3
expect "fuzz alone (black base), normal: LTC R" "albedo base_color=0 specular_weight=0 fuzz_weight=1 wo 0 0 1 $A" "- - -" 0
expect "coat over white lambert (no darkening for E_b=1)" "albedo $LAMBERT coat_weight=1 wo 0.6 0 0.8 $A" "1 1 1" 2e-3
expect "coat over grey lambert, darkening=1" "albedo base_color=0.5 specular_weight=0 coat_weight=1 wo 0 0 1 $A" "- - -" 0
expect "coat over grey lambert, darkening=0" "albedo base_color=0.5 specular_weight=0 coat_weight=1 coat_darkening=0 wo 0 0 1 $A" "- - -" 0
expect "thin film on black dielectric (iridescent)" "albedo base_color=0 thin_film_weight=1 wo 0 0 1 $A" "- - -" 0

echo "== transmission convention: f(out->in)/f(in->out) = eta^2 = 2.25 (no radiance 1/eta^2 scaling)"
f1=$(printf 'eval %s wo 0.6 0 0.8 wi -0.3 0 -0.953939201\n' "$GLASS" | "$oracle" | cut -d' ' -f1)
f2=$(printf 'eval %s wo -0.3 0 -0.953939201 wi 0.6 0 0.8\n' "$GLASS" | "$oracle" | cut -d' ' -f1)
ratio=$(awk -v a="$f1" -v b="$f2" 'BEGIN { printf "%.4f", a / b }')
report "glass transmission ratio" "$(within "$ratio" 2.25 0.02)" "f_out_in=$f1 f_in_out=$f2 ratio=$ratio"

echo "== eval integrated over the sphere (uniform, n=200000) vs albedo: checks the cosine was divided out"
for m in "$LAMBERT" "$METAL" "transmission_weight=1 specular_roughness=0.7" "base_color=0.3,0.5,0.7 fuzz_weight=1 coat_weight=1 coat_roughness=0.4"; do
    r=$(integrate "$m" "0.6 0 0.8" 200000 5)
    a=$(printf 'albedo %s wo 0.6 0 0.8 n 200000 seed 2\n' "$m" | "$oracle" | cut -d' ' -f1)
    set -- $r
    report "[$m]" "$(within "$1" "$a" 0.02)" "integral(f|cos|)=$1 albedo_r=$a integral(pdf)=$2"
done

echo "== malformed lines answer 'error ...' and do not stop the stream"
out=$(printf 'eval wo 0 0 1 wi 0 0 1\neval foo=1 wo 0 0 1 wi 0 0 1\nnonsense\neval base_color=1,2 wo 0 0 1 wi 0 0 1\nalbedo wo 0 0 2 n 10 seed 1\nalbedo wo 0 0 1 n 10\neval wo 0 0 1 wi 0 0 1\n' | "$oracle")
ok=$(printf '%s\n' "$out" | awk 'NR>=2 && NR<=6 && $1!="error"{bad=1} (NR==1||NR==7) && $1=="error"{bad=1} END{print (NR==7 && !bad) ? 1 : 0}')
report "7 lines in, 7 answers, lines 2-6 are errors" "$ok" "$(printf '%s\n' "$out" | tr '\n' '|')"

echo "failures: $failures"
[ "$failures" = 0 ]
