include(GoogleTest)

# Test timeouts are set for an optimised build. The sanitizer build runs the
# same tests several times slower (measured 2026-12-02: SettledBed 2.45 s
# Release, 18.3 s ASan+UBSan; the settling fast tier 773 s of its 900 s limit
# at load 11), so its timeouts scale by 4; a loaded machine may ask for more
# (-DFDEM_TEST_TIMEOUT_SCALE=N). Timeouts stay finite: they catch hangs.
set(FDEM_TEST_TIMEOUT_SCALE "" CACHE STRING "Factor on every test timeout (empty: 4 with FDEM_SANITIZE, else 1)")
if(FDEM_TEST_TIMEOUT_SCALE STREQUAL "")
  if(FDEM_SANITIZE)
    set(fdem_timeout_scale 4)
  else()
    set(fdem_timeout_scale 1)
  endif()
elseif(FDEM_TEST_TIMEOUT_SCALE MATCHES "^[1-9][0-9]*$")
  set(fdem_timeout_scale ${FDEM_TEST_TIMEOUT_SCALE})
else()
  message(FATAL_ERROR "FDEM_TEST_TIMEOUT_SCALE must be a positive whole number, got '${FDEM_TEST_TIMEOUT_SCALE}'")
endif()

# fdem_scaled_timeout(OUT seconds): seconds times the build's timeout factor;
# every test's TIMEOUT goes through it.
function(fdem_scaled_timeout OUT SECONDS)
  math(EXPR scaled "${SECONDS} * ${fdem_timeout_scale}")
  set(${OUT} ${scaled} PARENT_SCOPE)
endfunction()


# The sanitizer build (scripts/test.sh --sanitize, CI's second half) runs the
# unit, verification and mpi tiers, so it builds no executable that only the
# main job or the nightly tier runs: under ASan + UBSan those full-size studies
# would take hours, and compiling them cost ~10 % of a cold sanitizer build
# (2026-12-06). FDEM_SANITIZE_ALL_TIERS=ON builds them anyway.
option(FDEM_SANITIZE_ALL_TIERS "In the sanitizer build, also build the main-job and nightly executables" OFF)
# fdem_tier_built(LABEL OUT): whether this build makes an executable for tier LABEL.
function(fdem_tier_built LABEL OUT)
  if(FDEM_SANITIZE AND NOT FDEM_SANITIZE_ALL_TIERS AND LABEL MATCHES "^(main|nightly)$")
    set(${OUT} OFF PARENT_SCOPE)
  else()
    set(${OUT} ON PARENT_SCOPE)
  endif()
endfunction()

option(FDEM_UNITY_TESTS "Compile each test executable's files as one unit (faster cold builds)" ON)

# fdem_add_gtest(NAME LABEL <unit|verification|nightly> SOURCES ... [LIBS ...] [TIMEOUT s]
#                [DEFINES ...] [TEST_PREFIX p])
# One GoogleTest executable; each TEST becomes a ctest entry carrying LABEL,
# so `ctest -L unit` and `ctest -L verification` select the tiers. DEFINES and
# TEST_PREFIX build a second variant of a case file (e.g. with another solver)
# whose ctest names do not collide with the first's.
# Without FDEM_BUILD_TESTS it defines nothing (the solver builds without GoogleTest).
function(fdem_add_gtest NAME)
  if(NOT FDEM_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(T "" "LABEL;TIMEOUT;TEST_PREFIX" "SOURCES;LIBS;DEFINES" ${ARGN})
  if(NOT T_LABEL)
    message(FATAL_ERROR "fdem_add_gtest(${NAME}): LABEL is required")
  endif()
  fdem_tier_built(${T_LABEL} built)
  if(NOT built)
    return()
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  fdem_scaled_timeout(T_TIMEOUT ${T_TIMEOUT})
  add_executable(${NAME} ${T_SOURCES})
  # Test files of one executable compile as one unit: they share GoogleTest's
  # and Eigen's instantiations, which separate units each compile and
  # optimise again (ASan + UBSan, six hard-case files: 116 core-seconds
  # apart, 52 together, 2026-12-07). So their file-local names must differ.
  set_target_properties(${NAME} PROPERTIES UNITY_BUILD ${FDEM_UNITY_TESTS} UNITY_BUILD_BATCH_SIZE 0)
  target_link_libraries(${NAME} PRIVATE fdem_solver fdem_options GTest::gtest GTest::gtest_main ${T_LIBS})
  target_compile_definitions(${NAME} PRIVATE
    FDEM_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    FDEM_BINARY_DIR="${PROJECT_BINARY_DIR}"
    FDEM_RESULTS_DIR="${FDEM_RESULTS_DIR}"
    FDEM_PYTHON="${Python3_EXECUTABLE}"
    ${T_DEFINES})
  # The fast tiers run one test per core, so each gets one OpenMP thread:
  # two threads per test on 2 shared cores wait at every barrier (measured
  # 10-100x slower). Tests about threading set their own counts; the nightly
  # tier keeps the machine's default.
  set(env_props "")
  if(NOT T_LABEL STREQUAL "nightly")
    set(env_props ENVIRONMENT OMP_NUM_THREADS=1)
  endif()
  # A fast-tier test linking the study writer (fdem_study_io) writes
  # results/<study>/, which reports.study_results_report reads: it sets up
  # that fixture, so ctest runs the report after it rather than beside it
  # (beside it the report once read a study's files mid-rewrite and failed).
  if(T_LABEL STREQUAL "verification" AND "fdem_study_io" IN_LIST T_LIBS)
    list(APPEND env_props FIXTURES_SETUP fdem_study_results)
  endif()
  # Discovery runs the executable with --gtest_list_tests before its tests;
  # CMake's 5 s default is too short for a sanitizer build on a loaded host.
  gtest_discover_tests(${NAME}
    DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
    TEST_PREFIX "${T_TEST_PREFIX}"
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    PROPERTIES LABELS ${T_LABEL} TIMEOUT ${T_TIMEOUT} ${env_props})
endfunction()

# fdem_add_study_tier(NAME TARGET <exe> TIER <tier> STUDY <study> LABEL <label> TIMEOUT s
#                     [SETS_UP_RESULTS] [DEPENDS <test>...])
# One ctest entry of a study that runs a tier in one process and checks its
# gates after (verification/support/study_main.hpp): `<exe> --tier=<tier>`
# from the build tree, one OpenMP thread (a single grain or a small mesh: threads
# only add synchronisation on the loaded 2-core host, measured 10x slower, and
# make the wall-time columns depend on the load), holding the study's results
# folder. SETS_UP_RESULTS: the fast tier, which the report's tests need first.
function(fdem_add_study_tier NAME)
  cmake_parse_arguments(T "SETS_UP_RESULTS" "TARGET;TIER;STUDY;LABEL;TIMEOUT" "DEPENDS" ${ARGN})
  add_test(NAME ${NAME} COMMAND ${T_TARGET} --tier=${T_TIER})
  fdem_scaled_timeout(T_TIMEOUT ${T_TIMEOUT})
  set(props LABELS ${T_LABEL} TIMEOUT ${T_TIMEOUT} WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
            RESOURCE_LOCK fdem_results_${T_STUDY} ENVIRONMENT "OMP_NUM_THREADS=1")
  if(T_SETS_UP_RESULTS)
    list(APPEND props FIXTURES_SETUP fdem_study_results)
  endif()
  if(T_DEPENDS)
    list(APPEND props DEPENDS ${T_DEPENDS})
  endif()
  set_tests_properties(${NAME} PROPERTIES ${props})
endfunction()
