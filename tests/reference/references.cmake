# Reference-image tests (label "reference"): lray-compare renders every case
# of tests/reference/gallery.toml (each gallery scene, small, on both
# backends) and compares it with its approved image there. A failure leaves
# an HTML report (new, approved, heat map, slider) in
# <build>/reference-report/index.html and JUnit XML beside it.
add_test(NAME reference.gallery
         COMMAND lray-compare --suite ${CMAKE_SOURCE_DIR}/tests/reference/gallery.toml
                 --out ${CMAKE_BINARY_DIR}/reference-out
                 --html ${CMAKE_BINARY_DIR}/reference-report
                 --junit ${CMAKE_BINARY_DIR}/reference-report/junit.xml)
set_tests_properties(reference.gallery PROPERTIES LABELS reference TIMEOUT 600)
