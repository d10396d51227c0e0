# SPDX-License-Identifier: MIT
# The accuracy targets of the T-S network on the default digital twin (docs/training.md,
# "Accuracy"), on the paper's own recipe: train on L18 x 3, test on 270 Latin-hypercube moves,
# for three seed pairs (train, test) = (1, 2), (11, 12), (21, 22):
#  - reduction >= the paper's Table 5 for every parameter;
#  - mean |residual| <= 1.5 x the noise floor (0.8 sigma of Table 1) for all four parameters.
#  Known unmet (docs/training.md, "Why RPE's residual misses"): RPE's residual limit, which even
#  the quadratic through the L18's nine (PV, PD) cell means misses (accuracy_l18_cell_interpolant):
#  RPE bends along the triangular boundary PD = PV^2/PA between the levels. The test requires it
#  to be still unmet (the list cannot outlive its reason) and every other target met, RPE's
#  reduction included.
# The 5-input model (with Y) on a Y-varying design (the shipped recipe: L18 x 3 with Y at 0, 250,
# 500, seed 1, plus 540 Latin-hypercube moves, seed 3; test LHS 270 with Y varying, seed 2) meets
# every residual limit.
# Usage: cmake -DSIM=... -DTRAIN=... -DWORK=... -P fnn_accuracy.cmake
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY "${WORK}")

include(${CMAKE_CURRENT_LIST_DIR}/run_command.cmake)

# Paper's Table 5 reductions [%] and 1.5 x 0.8 sigma of Table 1 [um].
set(paper_reduction_mpe 88.8)
set(paper_reduction_rpe 90.8)
set(paper_reduction_mae 80.2)
set(paper_reduction_rae 71.3)
set(limit_mpe 1.59)
set(limit_rpe 0.555)
set(limit_mae 0.735)
set(limit_rae 0.36)

set(failures "")
# target(NAME MISSED WHY KNOWN_UNMET): appends WHY to `failures` if the target NAME (e.g.
# rpe_residual) is missed, or if it is listed in KNOWN_UNMET and now met (update the docs and the
# list).
macro(target name missed why known_unmet)
  if(${name} IN_LIST ${known_unmet})
    if(${missed})
      message(STATUS "${_label} ${name}: known unmet, still unmet")
    else()
      string(APPEND failures "${_label} ${name}: listed as known unmet but now met: update the list and docs/training.md\n")
    endif()
  elseif(${missed})
    string(APPEND failures "${why}")
  endif()
endmacro()

# check(NAME JSON CHECK_REDUCTION KNOWN_UNMET): every reduction (if CHECK_REDUCTION) and every
# mean residual of the four parameters, through target().
macro(check label json check_reduction known_unmet)
  set(_label "${label}")
  foreach(p mpe rpe mae rae)
    string(JSON reduction GET "${json}" ${p} reduction_pct)
    string(JSON after GET "${json}" ${p} mean_after_um)
    string(JSON before GET "${json}" ${p} mean_before_um)
    message(STATUS "${label} ${p}: mean before ${before} um, mean residual ${after} um "
                   "(limit ${limit_${p}}), reduction ${reduction} % (paper ${paper_reduction_${p}})")
    set(missed FALSE)
    if(${check_reduction} AND reduction LESS paper_reduction_${p})
      set(missed TRUE)
    endif()
    target(${p}_reduction ${missed}
           "${label} ${p}: reduction ${reduction} % < paper ${paper_reduction_${p}} %\n" ${known_unmet})
    set(missed FALSE)
    if(after GREATER limit_${p})
      set(missed TRUE)
    endif()
    target(${p}_residual ${missed}
           "${label} ${p}: mean residual ${after} um > ${limit_${p}} um\n" ${known_unmet})
  endforeach()
endmacro()

set(l18_known_unmet rpe_residual)
set(none "")
foreach(pair "1;2" "11;12" "21;22")
  list(GET pair 0 train_seed)
  list(GET pair 1 test_seed)
  run(${SIM} dataset --design l18 --repeats 3 --noise --seed ${train_seed} -o ${WORK}/l18x3-${train_seed}.csv)
  run(${SIM} dataset --design lhs --samples 270 --noise --seed ${test_seed} -o ${WORK}/lhs270-${test_seed}.csv)
  # Ridge calibration folds: this test measures the networks' residuals, which the interval's
  # calibration does not change (FnnTrainerInterval.AsServedFoldsFollowTheServedModel… asserts
  # it), and the five fold networks trained as served would take most of its time (minutes
  # under ASan).
  run(${TRAIN} fit ${WORK}/l18x3-${train_seed}.csv --interval-folds ridge -o ${WORK}/l18-${train_seed}.json)
  run(${TRAIN} eval ${WORK}/l18-${train_seed}.json ${WORK}/lhs270-${test_seed}.csv --json)
  check("L18x3 seed ${train_seed} -> LHS270 seed ${test_seed}" "${run_out}" TRUE l18_known_unmet)
endforeach()

# Escaped semicolons: one argument through run()'s list.
set(levels_y [=[pv=40,70,100\;pd=40,60,80\;av=8,12,16\;ad=5,10,15\;y=0,250,500]=])
run(${SIM} dataset --design l18 --repeats 3 --noise --seed 1 --levels "${levels_y}" -o ${WORK}/l18x3-y.csv)
run(${SIM} dataset --design lhs --samples 270 --noise --seed 2 --levels "${levels_y}" -o ${WORK}/lhs270-y.csv)
run(${SIM} dataset --design lhs --samples 540 --noise --seed 3 --levels "${levels_y}" -o ${WORK}/lhs540-y.csv)
file(READ ${WORK}/l18x3-y.csv l18y_text)
file(STRINGS ${WORK}/lhs540-y.csv lhsy_lines)
list(REMOVE_AT lhsy_lines 0)
list(JOIN lhsy_lines "\n" lhsy_text)
file(WRITE ${WORK}/l18x3-lhs540-y.csv "${l18y_text}${lhsy_text}\n")
run(${TRAIN} fit ${WORK}/l18x3-lhs540-y.csv --inputs pv,pd,av,ad,y --max-iterations 0 -o ${WORK}/y.json)
run(${TRAIN} eval ${WORK}/y.json ${WORK}/lhs270-y.csv --json)
check("5-input L18x3+LHS540 (Y varying) -> LHS270 (Y varying) seed 2" "${run_out}" FALSE none)

if(failures)
  message(FATAL_ERROR "accuracy targets missed:\n${failures}")
endif()
