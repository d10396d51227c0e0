# SPDX-License-Identifier: MIT
# The accuracy targets of the T-S network on the default digital twin (docs/training.md,
# "Accuracy"): train on L18 x 3 (seed 1), test on 270 Latin-hypercube moves (seed 2).
#  - reduction >= the paper's Table 5 for every parameter;
#  - mean |residual| <= 1.5 x the noise floor (0.8 sigma of Table 1) for MPE, RPE and MAE;
#  - RAE's twin response oscillates between the L18 levels, and its 1.5 x floor target (0.36 um)
#    is NOT met by L18 training (docs/training.md). Trained on L18 x 3 plus a 270-move Latin
#    hypercube (seed 3; the shipped default model's recipe), every target is met: checked too.
# Usage: cmake -DSIM=... -DTRAIN=... -DWORK=... -P fnn_accuracy.cmake
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY "${WORK}")

include(${CMAKE_CURRENT_LIST_DIR}/run_command.cmake)

run(${SIM} dataset --design l18 --repeats 3 --noise --seed 1 -o ${WORK}/l18x3.csv)
run(${SIM} dataset --design lhs --samples 270 --noise --seed 2 -o ${WORK}/lhs270.csv)
run(${SIM} dataset --design lhs --samples 270 --noise --seed 3 -o ${WORK}/lhs270-train.csv)
run(${TRAIN} fit ${WORK}/l18x3.csv -o ${WORK}/l18.json)
file(READ ${WORK}/l18x3.csv l18_text)
file(STRINGS ${WORK}/lhs270-train.csv lhs_lines)
list(REMOVE_AT lhs_lines 0)
list(JOIN lhs_lines "\n" lhs_text)
file(WRITE ${WORK}/l18x3-lhs270.csv "${l18_text}${lhs_text}\n")
run(${TRAIN} fit ${WORK}/l18x3-lhs270.csv -o ${WORK}/lhs.json)
run(${TRAIN} eval ${WORK}/l18.json ${WORK}/lhs270.csv --json)
set(l18 "${run_out}")
run(${TRAIN} eval ${WORK}/lhs.json ${WORK}/lhs270.csv --json)
set(lhs "${run_out}")

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
foreach(p mpe rpe mae rae)
  string(JSON reduction GET "${l18}" ${p} reduction_pct)
  string(JSON after GET "${l18}" ${p} mean_after_um)
  string(JSON after_lhs GET "${lhs}" ${p} mean_after_um)
  message(STATUS "${p}: L18-trained reduction ${reduction} % (paper ${paper_reduction_${p}}), "
                 "mean residual ${after} um; L18+LHS-trained ${after_lhs} um; limit ${limit_${p}} um")
  if(reduction LESS paper_reduction_${p})
    string(APPEND failures "${p}: reduction ${reduction} % < paper ${paper_reduction_${p}} %\n")
  endif()
  if(NOT p STREQUAL "rae" AND after GREATER limit_${p})
    string(APPEND failures "${p}: L18-trained mean residual ${after} um > ${limit_${p}} um\n")
  endif()
  if(after_lhs GREATER limit_${p})
    string(APPEND failures "${p}: L18+LHS-trained mean residual ${after_lhs} um > ${limit_${p}} um\n")
  endif()
endforeach()
if(failures)
  message(FATAL_ERROR "accuracy targets missed:\n${failures}")
endif()
