# The registration list: every sensor family rangekit builds, one line each, in this order.
# The libraries, link rules, the C++ X-macro, the dashboard's and Python's lists all follow it
# (cmake/family.cmake; docs/architecture.md, "Add a family").
set(RANGEKIT_FAMILIES
  uls
  ls5
)
