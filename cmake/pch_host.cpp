// The precompiled headers of cmake/CompileTime.cmake are built with this empty source.
