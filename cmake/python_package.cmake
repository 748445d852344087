# Assembles the Python package plumetrace in DEST (cmake -DSRC=... -DDEST=... -P this file): the
# sources of python/plumetrace, plus what it ships from elsewhere in the repository (package
# data): the studies' report code and sweep files, the scenarios the sweep files name (their
# relative paths stay valid: ../../../scenarios from studies/lochmatter2008/sets/), and the
# Python example controller. The build's copy (build/python) and the wheel of `pip install .`
# (setup.py packs the folder this makes) are the same files. file(COPY) skips files already up
# to date, so a build never rewrites what a running test may be importing.
foreach(var SRC DEST)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "python_package.cmake: -D${var}=... is required")
  endif()
endforeach()
set(pkg ${DEST}/plumetrace)

# (a module an editable install left in the sources is not this build's)
file(COPY ${SRC}/python/plumetrace DESTINATION ${DEST}
     PATTERN __pycache__ EXCLUDE PATTERN "*.pyc" EXCLUDE PATTERN "_core.*" EXCLUDE)
# the studies: what `plumetrace.studies.NAME` finds (sweep files, presets, study.toml) and
# the reports' code kept beside the study
foreach(study lochmatter2008 meander baselines benchmark)
  file(COPY ${SRC}/studies/${study}/ DESTINATION ${pkg}/studies/${study}
       FILES_MATCHING PATTERN "*.toml" PATTERN "*.py" PATTERN __pycache__ EXCLUDE)
endforeach()
file(COPY ${SRC}/scenarios/ DESTINATION ${pkg}/scenarios FILES_MATCHING PATTERN "*.toml")
# the example controller the README imports (plumetrace.examples.python_surge_cast)
file(COPY ${SRC}/examples/python_surge_cast.py DESTINATION ${pkg}/examples)
# the documents the reports cite, copied beside each report (plumetrace/report/page.py)
file(COPY ${SRC}/docs/ DESTINATION ${pkg}/docs FILES_MATCHING PATTERN "*.md")
