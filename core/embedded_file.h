#pragma once
// A file compiled into the program's read-only data by the assembler's .incbin (no generated C
// array: megabytes of one take the compiler minutes). CANDELA_EMBED_FILE(name, "path") at
// namespace scope in one .cpp defines the hidden symbols name_begin and name_end around the
// file's bytes (16-byte aligned); CANDELA_EMBEDDED_FILE_SYMBOLS(name) declares them where they are
// read. The path comes from CMakeLists.txt, with the file's MD5 on the same command line, so that
// ccache, which does not read .incbin files, compiles the .cpp again when the file changes.

// clang-format off
#define CANDELA_EMBED_FILE(name, path)                           \
    asm(".pushsection .rodata, \"a\"\n"                          \
        ".balign 16\n"                                            \
        ".globl " #name "_begin\n"                                \
        ".hidden " #name "_begin\n"                               \
        #name "_begin:\n"                                         \
        ".incbin \"" path "\"\n"                                  \
        ".globl " #name "_end\n"                                  \
        ".hidden " #name "_end\n"                                 \
        #name "_end:\n"                                           \
        ".popsection\n")
// clang-format on

#define CANDELA_EMBEDDED_FILE_SYMBOLS(name)                                          \
    extern "C" {                                                                     \
    __attribute__((visibility("hidden"))) extern const unsigned char name##_begin[]; \
    __attribute__((visibility("hidden"))) extern const unsigned char name##_end[];   \
    }
