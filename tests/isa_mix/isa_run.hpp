#pragma once
/// What each unit of the ISA-mix program reports.
struct IsaRun {
    const char* tag;   ///< secchi::isa_tag of the unit
    double ed, ed_se;  ///< Ed at 2 m and its standard error
};
