#!/usr/bin/env bash
# Runs the studies of cases/studies with `cosim study` and copies each study.csv / study.png into
# docs/results/studies/<name>/ (the per-run folders stay in results/studies/<name>/).
# usage: cases/studies/run_studies.sh [NAME ...]   (no NAME: all, in the order below)
# Environment: COSIM (default build/bin/cosim), EXTRA (more cosim options, quoted as on a
# command line, e.g. EXTRA='--set "SPH/Hourglass fading=false"'),
# SPACING (a particle spacing [m] for every run of the study), SUFFIX (appended to the study's
# folder names), e.g. SPACING=0.005 SUFFIX=-5mm.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
cosim="${COSIM:-build/bin/cosim}"
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}" # shared machine: do not spin at barriers
# the default cases: the BTS one is the flattened body-fitted disc, the rock of every case is the
# Hoek-Brown envelope with which the simulator reproduces Table 3 (Rock/Strength parameters =
# simulated)
disc=cases/bts/bts.prm
# the studies stored before those became the defaults ran the round lattice disc and Mohr-Coulomb
# with Table 4's c, phi: they keep them (`pin` goes in front of each study's own keys; the groups
# studies clear it)
bts=cases/bts/bts-round.prm
pin=(--set "Rock/Model=mohr-coulomb" --set "Rock/Strength parameters=calibrated")
# the groups studies of the Mohr-Coulomb rock with the simulator's c, phi (the UCS and BTS cases'
# default before their Hoek-Brown rock)
mc=(--set "Rock/Model=mohr-coulomb")
flat=cases/bts/bts-flattened.prm
ucs=cases/ucs/ucs.prm
ctcs=cases/ctcs/ctcs.prm
quick=(--set "Output/Snapshots=2")
het=(--set "Rock/Strength scatter=10" --set "Rock/Scatter length=0.005" --set "Rock/Softening law=fracture energy")
steel=(--set "Platens/Model=elastic")
rollers=("${steel[@]}" --set "Platens/Diameter=0.05" --set "Platens/Loaded face=roller")
fitted=(--set "SPH/Particle arrangement=body-fitted")
fitted_rollers=("${rollers[@]}" "${fitted[@]}")
spacings=(--vary "SPH/Particle spacing=0.005,0.0025,0.00125")
# every spacing with the coarser meshes (elements finer than the particles are refused)
grid=(--vary "Platens/Element size=0.01,0.005" "${spacings[@]}")
plastic=(--set "Rock/Residual fraction=1" --set "Loading/End strain=0.005") # no softening
# the crack band with a shear fault's fracture energy (G_II = 100 G_I = 1e4 J/m^2, Wong 1982):
# compressive failure regularised at spacings below 12 mm (a band of 2 dx under 2 E G_II / UCS^2 = 24 mm)
shear=(--set "Rock/Softening law=fracture energy" --set "Rock/Shear fracture energy ratio=100")
if [ -n "${SPACING:-}" ]; then quick+=(--set "SPH/Particle spacing=$SPACING"); fi
eval "extra=(${EXTRA:-})" # keys with spaces stay one word

study() { # NAME CASE ARGS...
  local name=$1${SUFFIX:-} case=$2
  shift 2
  echo "== $name: cosim study $case ${pin[*]} $* -o results/studies/$name --force" >&2
  "$cosim" study "$case" "${pin[@]}" "$@" "${quick[@]}" "${extra[@]}" -o "results/studies/$name" --force || true
  mkdir -p "docs/results/studies/$name"
  for f in study.csv study.png; do
    if [ -f "results/studies/$name/$f" ]; then cp "results/studies/$name/$f" "docs/results/studies/$name/"; fi
  done
}

unpinned() { # the same with the cases' own rock (no pin)
  local pin=()
  study "$@"
}

run() {
  case $1 in
    bts-groups)   unpinned bts-groups $disc "${mc[@]}" --groups all ;;
    bts-groups-1mm) unpinned bts-groups-1mm $disc "${mc[@]}" --set "SPH/Particle spacing=0.001" --groups M1,M4,M7,M10 ;;
    bts-rate)     study bts-rate $bts --key "Loading/Strain rate" --values 0.25,0.5,1,2,5,10,20 ;;
    # the 25 mm disc allows at most 2.5 mm (10 particles through the thickness): Table 1's 50 mm
    # discs. 50/12 and 50/15 mm stand in for 4 and 3 mm, which do not divide 50 mm (they started
    # with the platens inside the lattice in older versions; bts-spacing-paper has them).
    bts-spacing)  study bts-spacing $bts --set "Test/Length=0.05" --key "SPH/Particle spacing" \
                    --values 0.005,0.0041667,0.0033333,0.0025,0.002 ;;
    bts-spacing-paper) study bts-spacing-paper $bts --set "Test/Length=0.05" --key "SPH/Particle spacing" \
                    --values 0.005,0.004,0.003,0.0025,0.002 ;;
    bts-tssfac)   study bts-tssfac $bts --key "SPH/TSSFAC" --values 0.7,0.8,0.9 ;;
    bts-form)     study bts-form $bts --key "SPH/FORM" --values 0,1,7,8 ;;
    bts-cslh)     study bts-cslh $bts --key "SPH/CSLH" --values 1.05,1.2,1.3 ;;
    ucs-groups)   unpinned ucs-groups $ucs "${mc[@]}" --groups all ;;
    # the cases' Hoek-Brown rock (the simulator's m_b or cut-off, the default of every case)
    bts-groups-hb) unpinned bts-groups-hb $disc --set "Rock/Model=hoek-brown" --groups all ;;
    bts-groups-1mm-hb) unpinned bts-groups-1mm-hb $disc --set "Rock/Model=hoek-brown" \
                    --set "SPH/Particle spacing=0.001" --groups M1,M4,M7,M10 ;;
    ucs-groups-hb) unpinned ucs-groups-hb $ucs --set "Rock/Model=hoek-brown" --groups all ;;
    # the paper's 1 mm (197,600 particles): 20-40 min per group on this machine
    ucs-groups-1mm) study ucs-groups-1mm $ucs --set "SPH/Particle spacing=0.001" --groups all ;;
    ucs-loaded-face) study ucs-loaded-face $ucs --key "SPH/Loaded face correction" --values false,true ;;
    ucs-spacing)  study ucs-spacing $ucs --key "SPH/Particle spacing" --values 0.005,0.004,0.003,0.0025 ;;
    # 5 mm: a slow rate costs its inverse in steps (the default 2.5 mm derives about 4 /s)
    ucs-rate)     study ucs-rate $ucs --set "SPH/Particle spacing=0.005" --key "Loading/Strain rate" \
                    --values 0.5,1,2,5,10,20 ;;
    ucs-tssfac)   study ucs-tssfac $ucs --key "SPH/TSSFAC" --values 0.7,0.8,0.9 ;;
    ucs-form)     study ucs-form $ucs --key "SPH/FORM" --values 0,1,7,8 ;;
    ucs-cslh)     study ucs-cslh $ucs --key "SPH/CSLH" --values 1.05,1.2,1.3 ;;
    # the platen study (cases/studies/platens/README.md): rigid and elastic steel, free slip,
    # Coulomb friction and a bonded interface; UCS at L/D 1, 2 and 2.5
    platens-ucs)  study platens-ucs $ucs --vary "Platens/Model=rigid,elastic" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" --vary "Test/Length=0.05,0.1,0.125" ;;
    platens-ucs-bonded) study platens-ucs-bonded $ucs --set "Platens/Bonded=true" \
                    --vary "Platens/Model=rigid,elastic" --vary "Test/Length=0.05,0.1,0.125" ;;
    # the same with the cases' default rock (Hoek-Brown, the simulator's envelope)
    platens-ucs-hb) unpinned platens-ucs-hb $ucs --vary "Platens/Model=rigid,elastic" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" --vary "Test/Length=0.05,0.1,0.125" ;;
    platens-ucs-bonded-hb) unpinned platens-ucs-bonded-hb $ucs --set "Platens/Bonded=true" \
                    --vary "Platens/Model=rigid,elastic" --vary "Test/Length=0.05,0.1,0.125" ;;
    platens-bts-hb) unpinned platens-bts-hb $disc --vary "Platens/Model=rigid,elastic" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" ;;
    platens-bts-bonded-hb) unpinned platens-bts-bonded-hb $disc --set "Platens/Bonded=true" \
                    --vary "Platens/Model=rigid,elastic" ;;
    # that rock perfectly plastic (as cosim reference's) at three spacings: end friction on rigid
    # platens, bonded rigid and elastic platens
    platens-ucs-hb-plastic) unpinned platens-ucs-hb-plastic $ucs "${plastic[@]}" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" "${spacings[@]}" ;;
    platens-ucs-hb-plastic-bonded) unpinned platens-ucs-hb-plastic-bonded $ucs "${plastic[@]}" \
                    --set "Platens/Bonded=true" --vary "Platens/Model=rigid,elastic" \
                    "${spacings[@]}" ;;
    # that rock softening by the crack band with a shear fault's G_II at three spacings: end
    # friction on rigid platens, bonded rigid and elastic platens, G_II / 4 and x 4
    platens-ucs-hb-shear-energy) unpinned platens-ucs-hb-shear-energy $ucs "${shear[@]}" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" "${spacings[@]}" ;;
    platens-ucs-hb-shear-energy-bonded) unpinned platens-ucs-hb-shear-energy-bonded $ucs "${shear[@]}" \
                    --set "Platens/Bonded=true" --vary "Platens/Model=rigid,elastic" "${spacings[@]}" ;;
    platens-ucs-hb-shear-energy-length) unpinned platens-ucs-hb-shear-energy-length $ucs "${shear[@]}" \
                    --set "Platens/Friction coefficient=0.3" --vary "Platens/Model=rigid,elastic" \
                    --vary "Test/Length=0.05,0.1,0.125" --vary "SPH/Particle spacing=0.0025,0.00125" ;;
    platens-ucs-hb-shear-energy-ratio) unpinned platens-ucs-hb-shear-energy-ratio $ucs "${shear[@]}" \
                    --set "Platens/Friction coefficient=0.3" \
                    --vary "Rock/Shear fracture energy ratio=6.25,25,100,400" \
                    --vary "SPH/Particle spacing=0.0025,0.00125" ;;
    # the same on wide (1.2 D) elastic steel platens with mu 0.3: three spacings x three meshes
    platens-ucs-hb-shear-energy-grid) unpinned platens-ucs-hb-shear-energy-grid $ucs "${shear[@]}" \
                    "${steel[@]}" --set "Platens/Friction coefficient=0.3" "${grid[@]}" ;;
    platens-ucs-hb-shear-energy-wide-mu) unpinned platens-ucs-hb-shear-energy-wide-mu $ucs "${shear[@]}" \
                    "${steel[@]}" --set "Platens/Friction coefficient=0.1" --vary "SPH/Particle spacing=0.0025,0.00125" ;;
    platens-ucs-hb-shear-energy-fine) unpinned platens-ucs-hb-shear-energy-fine $ucs "${shear[@]}" \
                    "${steel[@]}" --set "Platens/Friction coefficient=0.3" --set "Platens/Element size=0.0025" \
                    --vary "SPH/Particle spacing=0.0025,0.00125" ;;
    # rigid platens on the body-fitted specimen (its side round: no staircase at the platen's rim)
    platens-ucs-fitted) study platens-ucs-fitted $ucs "${fitted[@]}" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" --vary "Test/Length=0.05,0.1,0.125" ;;
    platens-ucs-fitted-bonded) study platens-ucs-fitted-bonded $ucs "${fitted[@]}" --set "Platens/Bonded=true" \
                    --vary "Test/Length=0.05,0.1,0.125" ;;
    platens-bts)  study platens-bts $bts --vary "Platens/Model=rigid,elastic" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" ;;
    platens-bts-bonded) study platens-bts-bonded $bts --set "Platens/Bonded=true" \
                    --vary "Platens/Model=rigid,elastic" ;;
    # the reference study's flattened disc, body-fitted, at its converged 1.25 mm
    bts-flattened-spacing) study bts-flattened-spacing $flat \
                    --vary "SPH/Particle spacing=0.0025,0.00125,0.001,0.0008" ;;
    # hourglass control's coefficient /4 x4, dropped across tensile cracks (the default) or not
    bts-flattened-hourglass) study bts-flattened-hourglass $flat \
                    --vary "SPH/Hourglass coefficient=0.025,0.1,0.4" --vary "SPH/Hourglass fading=true,false" ;;
    platens-bts-flattened) study platens-bts-flattened $flat --vary "Platens/Model=rigid,elastic" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" ;;
    platens-bts-flattened-bonded) study platens-bts-flattened-bonded $flat --set "Platens/Bonded=true" \
                    --vary "Platens/Model=rigid,elastic" ;;
    # the BTS displacement at peak (cases/diagnose-basalt/README.md): crack closure against a
    # compliant load frame, on the 1.25 mm disc (spacing-converged) and the 2.5 mm cylinder
    basalt-bts-compliance) study basalt-bts-compliance $bts --set "SPH/Particle spacing=0.00125" \
                    --vary "Platens/Frame stiffness=0,5.3e8" --vary "Rock/Closure modulus ratio=1,0.3,0.2,0.1" ;;
    basalt-ucs-compliance) study basalt-ucs-compliance $ucs --set "Loading/End strain=0.03" \
                    --vary "Platens/Frame stiffness=0,5.3e8" --vary "Rock/Closure modulus ratio=1,0.3,0.2,0.1" ;;
    # the same on the default disc and cylinder with the cases' Hoek-Brown rock (the frame
    # stiffness k = P / (0.080 mm - d) from that disc's own peak load and displacement at 1.25 mm)
    basalt-bts-compliance-hb) unpinned basalt-bts-compliance-hb $disc --set "SPH/Particle spacing=0.00125" \
                    --vary "Platens/Frame stiffness=0,7.0e8" --vary "Rock/Closure modulus ratio=1,0.3,0.2,0.1" ;;
    basalt-ucs-compliance-hb) unpinned basalt-ucs-compliance-hb $ucs --set "Loading/End strain=0.03" \
                    --vary "Platens/Frame stiffness=0,7.0e8" --vary "Rock/Closure modulus ratio=1,0.3,0.2,0.1" ;;
    # 5 mm (10 particles across): 18 runs in the time budget of a shared machine
    ctcs)         study ctcs $ctcs --set "SPH/Particle spacing=0.005" --key "Test/Confining pressure" --values 10e6,30e6,50e6 \
                    --key "Rock/Strength parameters" --values calibrated,measured --groups M8,M9,M10 ;;
    # one curved envelope through UCS, BTS and triaxial strength (Rock/Strength parameters =
    # envelope, cosim calibrate --envelope), groups M8-M10 at the default 2.5 mm
    envelope-ucs) study envelope-ucs $ucs --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --groups M8,M9,M10 ;;
    envelope-bts) study envelope-bts $bts --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --groups M8,M9,M10 ;;
    envelope-ctcs) study envelope-ctcs $ctcs --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --key "Test/Confining pressure" \
                    --values 10e6,30e6,50e6 --groups M8,M9,M10 ;;
    # the envelope's tension cut-off calibrated through the flattened disc at 1.25 mm (cosim
    # calibrate --simulate cases/ucs/ucs.prm --set "Rock/Group=Mx" --set "Rock/Model=hoek-brown"
    # --set "Rock/Strength parameters=envelope" --set "SPH/Particle arrangement=body-fitted"
    # --cutoff-from cases/bts/bts-flattened.prm): M8 12.01, M9 9.47, M10 6.9618 MPa (the
    # cutoff_MPa of cases/data/simulator_calibrated.csv)
    envelope-cutoff-bts-M10) study envelope-cutoff-bts-M10 $flat --set "Rock/Group=M10" --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --set "Rock/Tensile strength=6.9618e6" \
                    --key "SPH/Particle spacing" --values 0.0025,0.00125,0.001 ;;
    envelope-cutoff-ctcs-M8|envelope-cutoff-ctcs-M9|envelope-cutoff-ctcs-M10)
                  g=${1##*-}; declare -A cut=([M8]=12.01e6 [M9]=9.47e6 [M10]=6.9618e6)
                  study "$1" $ctcs --set "Rock/Group=$g" --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --set "Rock/Tensile strength=${cut[$g]}" \
                    --key "Test/Confining pressure" --values 10e6,30e6,50e6 ;;
    # the disc's strength under the envelope's tension cut-off against the softening after it
    envelope-bts-softening) study envelope-bts-softening $bts --set "Rock/Model=hoek-brown" \
                    --set "Rock/Strength parameters=envelope" --set "Rock/Group=M10" \
                    --key "Rock/Softening strain" --values 0.0002,0.0005,0.002 ;;
    # heterogeneous rock (cases/studies/README.md): Weibull scatter m = 10 on 5 mm cells fixed in
    # space, crack-band softening; its convergence in spacing, then end friction and slenderness
    heterogeneous-ucs-spacing) study heterogeneous-ucs-spacing $ucs "${het[@]}" \
                    "${spacings[@]}" --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-ucs-1mm) study heterogeneous-ucs-1mm $ucs "${het[@]}" --set "SPH/Particle spacing=0.001" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-ucs-platens) study heterogeneous-ucs-platens $ucs "${het[@]}" \
                    --vary "Platens/Friction coefficient=0,0.1,0.3" --vary "Test/Length=0.05,0.1,0.125" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    # the same with the rock's c, phi from cosim calibrate --simulate --with-bts (2.5 mm)
    heterogeneous-calibrated-ucs-platens) study heterogeneous-calibrated-ucs-platens $ucs "${het[@]}" \
                    --set "Rock/Cohesion=4.69833e+07" --set "Rock/Friction angle=69.5227" \
                    --vary "Platens/Friction coefficient=0,0.3" --vary "Test/Length=0.05,0.1" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    # Table 4's phi with c scaled to the UCS alone (cosim calibrate --simulate, c x 1.877)
    heterogeneous-ucs-calibrated-friction) study heterogeneous-ucs-calibrated-friction $ucs "${het[@]}" \
                    --set "Rock/Cohesion=6.19148e+07" --vary "Platens/Friction coefficient=0,0.3" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    # ... and with G_I scaled by the strength squared (100 x 1.877^2): Table 4's rock's brittleness
    heterogeneous-ucs-calibrated-friction-scaled-energy) study heterogeneous-ucs-calibrated-friction-scaled-energy \
                    $ucs "${het[@]}" --set "Rock/Cohesion=6.19148e+07" --set "Rock/Fracture energy=352" \
                    --vary "Platens/Friction coefficient=0,0.3" --vary "Rock/Scatter seed=1,2,3" ;;
    # the same at 1.25 mm with that spacing's calibration (c 50.09 MPa, phi 68.22 deg)
    heterogeneous-calibrated-ucs-friction-1.25mm) study heterogeneous-calibrated-ucs-friction-1.25mm $ucs \
                    "${het[@]}" --set "Rock/Cohesion=5.00875e+07" --set "Rock/Friction angle=68.2224" \
                    --set "SPH/Particle spacing=0.00125" --vary "Platens/Friction coefficient=0,0.3" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    # the heterogeneous rock (Table 4's c, phi) with a shear fault's G_II: end friction at two spacings
    heterogeneous-ucs-shear-energy) study heterogeneous-ucs-shear-energy $ucs "${het[@]}" \
                    --set "Rock/Shear fracture energy ratio=100" --vary "Platens/Friction coefficient=0,0.3" \
                    --vary "SPH/Particle spacing=0.0025,0.00125" --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-ucs-bonded) study heterogeneous-ucs-bonded $ucs "${het[@]}" --set "Platens/Bonded=true" \
                    --vary "Test/Length=0.05,0.1,0.125" --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-bts-spacing) study heterogeneous-bts-spacing $bts "${het[@]}" \
                    --vary "SPH/Particle spacing=0.0025,0.00125,0.001" --vary "Rock/Scatter seed=1,2,3" ;;
    # the disc of the rock calibrated by cosim calibrate --simulate (c = 61.9 MPa at 2.5 mm)
    # against a tension cut-off and against the fracture energy
    heterogeneous-bts-cutoff) study heterogeneous-bts-cutoff $bts "${het[@]}" --set "Rock/Cohesion=61.9e6" \
                    --set "Rock/Model=mohr-coulomb-cutoff" --key "Rock/Tensile strength" --values 8e6,12e6,16e6,20e6 ;;
    heterogeneous-bts-fracture-energy) study heterogeneous-bts-fracture-energy $bts "${het[@]}" \
                    --set "Rock/Cohesion=61.9e6" --set "Rock/Model=mohr-coulomb-cutoff" \
                    --set "Rock/Tensile strength=10e6" --key "Rock/Fracture energy" --values 3,10,30,100 ;;
    # the same rock with the strain softening law: the heterogeneous specimen does not converge
    heterogeneous-ucs-strain-softening) study heterogeneous-ucs-strain-softening $ucs \
                    --set "Rock/Strength scatter=10" --set "Rock/Scatter length=0.005" \
                    "${spacings[@]}" ;;
    # elastic steel platens (60 mm wide, clamped to the rams) on the heterogeneous rock: end
    # friction and bonded ends, and the platen mesh (frictionless)
    heterogeneous-ucs-elastic-platens) study heterogeneous-ucs-elastic-platens $ucs "${het[@]}" \
                    --set "Platens/Model=elastic" --vary "Platens/Friction coefficient=0,0.1,0.3" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-ucs-elastic-bonded) study heterogeneous-ucs-elastic-bonded $ucs "${het[@]}" \
                    --set "Platens/Model=elastic" --set "Platens/Bonded=true" --vary "Rock/Scatter seed=1,2,3" ;;
    heterogeneous-ucs-elastic-mesh) study heterogeneous-ucs-elastic-mesh $ucs "${het[@]}" \
                    --set "Platens/Model=elastic" --vary "Platens/Element size=0.01,0.005,0.0025" \
                    --vary "Rock/Scatter seed=1,2,3" ;;
    # steel platens of the specimen's diameter on rollers (uniaxial throughout), perfectly plastic
    # and with the default softening: spacing with the elements at two spacings, and the mesh
    platens-rollers-spacing) study platens-rollers-spacing $ucs "${rollers[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" "${spacings[@]}" ;;
    # the same platens 0.5 to 2 mm wider than the specimen (ISRM allows up to D + 2 mm)
    platens-rollers-overhang) study platens-rollers-overhang $ucs "${steel[@]}" \
                    --set "Platens/Loaded face=roller" --vary "Rock/Residual fraction=1,0.1" \
                    --vary "Platens/Diameter=0.05,0.0505,0.051,0.052" ;;
    platens-rollers-mesh) study platens-rollers-mesh $ucs "${rollers[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" --vary "Platens/Element size=0.01,0.005,0.0025" ;;
    # the same on the body-fitted specimen (its side round: no staircase against the platen's rim)
    platens-rollers-spacing-fitted) study platens-rollers-spacing-fitted $ucs "${fitted_rollers[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" "${spacings[@]}" ;;
    platens-rollers-mesh-fitted) study platens-rollers-mesh-fitted $ucs "${fitted_rollers[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" --vary "Platens/Element size=0.01,0.005,0.0025" ;;
    platens-rollers-patch-fitted) study platens-rollers-patch-fitted $ucs "${fitted_rollers[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" --vary "Platens/Contact patch points=1,2,4,8,16" ;;
    # every spacing with the coarser meshes (the default softening; elements finer than the
    # particles are refused, and 2.5 mm elements at 2.5 and 1.25 mm are in -mesh- and -spacing-fitted)
    platens-rollers-grid-fitted) study platens-rollers-grid-fitted $ucs "${fitted_rollers[@]}" "${grid[@]}" ;;
    # the same with the cases' Hoek-Brown rock: three spacings x three meshes (elements finer
    # than the particles refused), and the interface's numbers x4 and /4
    platens-rollers-grid-hb) unpinned platens-rollers-grid-hb $ucs "${fitted_rollers[@]}" "${grid[@]}" ;;
    platens-rollers-fine-hb) unpinned platens-rollers-fine-hb $ucs "${fitted_rollers[@]}" \
                    --set "Platens/Element size=0.0025" --vary "SPH/Particle spacing=0.0025,0.00125" ;;
    platens-rollers-numerics-hb) unpinned platens-rollers-numerics-hb $ucs "${fitted_rollers[@]}" \
                    --vary "Platens/Contact tolerance=2.5e-7,1e-6,4e-6" --vary "Platens/Contact patch points=2,4,16" ;;
    # wider platens on the body-fitted specimen (ISRM: up to D + 2 mm), at three spacings
    platens-rollers-overhang-fitted) study platens-rollers-overhang-fitted $ucs "${steel[@]}" "${fitted[@]}" \
                    --set "Platens/Loaded face=roller" \
                    --vary "Platens/Diameter=0.051,0.052" "${spacings[@]}" ;;
    # the default steel platens (60 mm, clamped, elements of 2 dx) on the body-fitted specimen at
    # three spacings: frictionless (perfectly plastic, strain softening, crack band), with end
    # friction, bonded
    platens-wide-fitted) study platens-wide-fitted $ucs "${steel[@]}" "${fitted[@]}" \
                    --vary "Rock/Residual fraction=1,0.1" "${spacings[@]}" ;;
    platens-wide-fitted-crack-band) study platens-wide-fitted-crack-band $ucs "${steel[@]}" "${fitted[@]}" \
                    --set "Rock/Softening law=fracture energy" "${spacings[@]}" ;;
    platens-wide-fitted-friction) study platens-wide-fitted-friction $ucs "${steel[@]}" "${fitted[@]}" \
                    --vary "Platens/Friction coefficient=0.1,0.3" "${spacings[@]}" ;;
    # the cases' rock perfectly plastic on wide frictionless steel platens: does dilation (psi, not
    # measured; the cases' 0) make the peak converge?
    platens-wide-hb-dilation) unpinned platens-wide-hb-dilation $ucs "${steel[@]}" "${fitted[@]}" "${plastic[@]}" \
                    --vary "Rock/Dilation angle=0,15,30,45,60" "${spacings[@]}" ;;
    platens-wide-hb-dilation-shear-energy) unpinned platens-wide-hb-dilation-shear-energy $ucs "${steel[@]}" \
                    "${fitted[@]}" "${shear[@]}" --vary "Rock/Dilation angle=0,30" "${spacings[@]}" ;;
    platens-wide-fitted-bonded) study platens-wide-fitted-bonded $ucs "${steel[@]}" "${fitted[@]}" \
                    --set "Platens/Bonded=true" \
                    --vary "Rock/Residual fraction=1,0.1" "${spacings[@]}" ;;
    *) echo "unknown study $1" >&2; return 2 ;;
  esac
}

all=(bts-groups bts-groups-1mm bts-groups-hb bts-groups-1mm-hb ucs-groups-hb bts-rate bts-spacing bts-tssfac bts-form bts-cslh
     ucs-groups ucs-loaded-face ucs-spacing ucs-rate ucs-tssfac ucs-form ucs-cslh ctcs
     platens-ucs platens-ucs-bonded platens-ucs-fitted platens-ucs-fitted-bonded platens-bts platens-bts-bonded basalt-bts-compliance
     bts-flattened-spacing platens-bts-flattened platens-bts-flattened-bonded
     envelope-cutoff-bts-M10 envelope-cutoff-ctcs-M8 envelope-cutoff-ctcs-M9 envelope-cutoff-ctcs-M10
     basalt-ucs-compliance envelope-ucs envelope-bts envelope-ctcs envelope-bts-softening
     bts-flattened-hourglass heterogeneous-ucs-spacing heterogeneous-ucs-1mm heterogeneous-ucs-platens heterogeneous-ucs-bonded
     heterogeneous-calibrated-ucs-platens heterogeneous-calibrated-ucs-friction-1.25mm
     heterogeneous-ucs-calibrated-friction
     heterogeneous-ucs-strain-softening heterogeneous-bts-spacing heterogeneous-bts-cutoff
     heterogeneous-bts-fracture-energy heterogeneous-ucs-elastic-platens heterogeneous-ucs-elastic-bonded
     heterogeneous-ucs-elastic-mesh platens-rollers-spacing platens-rollers-mesh platens-rollers-overhang
     platens-rollers-spacing-fitted platens-rollers-mesh-fitted platens-rollers-patch-fitted
     platens-rollers-overhang-fitted platens-rollers-grid-fitted
     platens-wide-fitted platens-wide-fitted-crack-band platens-wide-fitted-friction
     platens-wide-fitted-bonded platens-ucs-hb platens-ucs-bonded-hb platens-bts-hb platens-bts-bonded-hb
     platens-ucs-hb-plastic platens-ucs-hb-plastic-bonded basalt-bts-compliance-hb basalt-ucs-compliance-hb
     platens-rollers-grid-hb platens-rollers-fine-hb platens-rollers-numerics-hb
     platens-ucs-hb-shear-energy platens-ucs-hb-shear-energy-bonded platens-ucs-hb-shear-energy-ratio
     platens-ucs-hb-shear-energy-grid platens-ucs-hb-shear-energy-fine platens-ucs-hb-shear-energy-wide-mu
     platens-wide-hb-dilation
     platens-wide-hb-dilation-shear-energy
     platens-ucs-hb-shear-energy-length heterogeneous-ucs-shear-energy)
for name in "${@:-${all[@]}}"; do
  run "$name"
done
