// Embeds the table file that generate_rgb_table writes at build time (path in
// TEX_RGB_TABLE_BIN, set by renderer/CMakeLists.txt) as read-only data: 9 MB of floats at
// resolution 64 would be slow to compile as a C++ array, the assembler copies it verbatim.
#ifndef TEX_RGB_TABLE_BIN
#error "TEX_RGB_TABLE_BIN must name the generated RGB-to-spectrum table (renderer/CMakeLists.txt)"
#endif

asm(".section .rodata\n"
    ".balign 64\n"
    ".global texRgbSigmoidTableBlob\n"
    ".hidden texRgbSigmoidTableBlob\n"
    "texRgbSigmoidTableBlob:\n"
    ".incbin \"" TEX_RGB_TABLE_BIN "\"\n"
    ".global texRgbSigmoidTableBlobEnd\n"
    ".hidden texRgbSigmoidTableBlobEnd\n"
    "texRgbSigmoidTableBlobEnd:\n"
    ".previous\n");
