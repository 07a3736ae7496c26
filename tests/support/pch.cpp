// The translation unit that builds the test programs' precompiled header (pch.hpp); it defines
// nothing.
