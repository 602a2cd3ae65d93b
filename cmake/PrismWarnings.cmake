# Warnings for our own code (third-party headers come in as SYSTEM includes).
add_compile_options("$<$<COMPILE_LANGUAGE:CXX>:-Wall;-Wextra;-Wno-unused-parameter>")
