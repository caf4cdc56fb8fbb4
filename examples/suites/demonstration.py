"""Write the bundled demonstration suite, dem_core/data/suites/demonstration: the four bundled records and 36
synthetic motions for studies of Greek monuments (dem_core.inputs.synthetic), each with its provenance in the
suite's records.csv.

    python examples/suites/demonstration.py [FOLDER]

Stochastic motions: 4 of each of 7 crustal scenarios, normal faulting (the Aegean's commonest) and strike-slip
(the North Aegean's), magnitudes 5.5 to 7, distances 5 to 50 km, on rock (Vs30 760 m/s) and stiff soil (400 m/s).
Near-fault motions: 4 of each of 2 scenarios within 5 km of the fault, each a stochastic motion with a
Mavroeidis-Papageorgiou velocity pulse.  Seeds are fixed, so the suite is made again identically with the pinned
numpy and pygmm (constraints.txt).
"""

import sys
from pathlib import Path

from dem_core.inputs.excitation import record
from dem_core.inputs.records import BUNDLED
from dem_core.inputs.suites import SuiteRecord, suite_folder, write_suite
from dem_core.inputs.synthetic import Scenario, near_fault_record, pulse_period, stochastic_motion

SEED = 2026
PER_SCENARIO = 4
STOCHASTIC = (Scenario(5.5, 10.0, 760.0, "NS"), Scenario(6.0, 5.0, 400.0, "NS"), Scenario(6.0, 20.0, 760.0, "NS"),
              Scenario(6.5, 10.0, 760.0, "NS"), Scenario(6.5, 30.0, 400.0, "NS"), Scenario(7.0, 20.0, 760.0, "SS"),
              Scenario(7.0, 50.0, 400.0, "NS"))
NEAR_FAULT = (Scenario(6.0, 3.0, 760.0, "NS"), Scenario(6.7, 5.0, 760.0, "SS"))
#: what is known of the bundled records: magnitude, distance (km), Vs30 (m/s), pulse period (s), where from
REAL = {
    "el_centro_1940": (6.95, 12.99, 213.44, None, "PEER NGA-West2 RSN6 (M, Rrup, Vs30)"),
    "mexico_city_1985": (8.0, None, None, None,
                         "Mw 8.0; SCT on the lake-bed clay, some 350 to 400 km from the rupture"),
    "northridge_1994": (6.69, 5.30, 440.54, 3.11, ("PEER NGA-West2 RSN1086 Sylmar - Olive View (M, Rrup, Vs30); "
                                                    "pulse period of Baker (2007)")),
    "kalamata_1986": (5.9, None, None, None, "Mw 5.9"),
}


def real_records() -> list:
    entries = []
    for name, (magnitude, distance, vs30, period, known) in REAL.items():
        numbers = {key: value for key, value in (("magnitude", magnitude), ("distance_km", distance),
                                                 ("vs30", vs30), ("pulse_period", period)) if value is not None}
        entries.append(SuiteRecord(name, record(name), name,
                                   f"recorded: {BUNDLED[name].description}; {known} (dem_core/data/records/"
                                   f"SOURCES.md)", **numbers))
    return entries


def synthetic_records() -> list:
    entries = []
    for number, scenario in enumerate(STOCHASTIC):
        for index in range(PER_SCENARIO):
            name = f"stochastic_{number + 1}{'abcd'[index]}"
            motion = stochastic_motion(scenario, SEED + number, index)
            entries.append(SuiteRecord(name, motion, f"{name}.txt",
                                       f"synthetic, stochastic: {scenario.label}; Bayless-Abrahamson 2019 spectrum, "
                                       f"Afshari-Stewart 2016 D5-95, seed {SEED + number}-{index}",
                                       magnitude=scenario.magnitude, distance_km=scenario.distance_km,
                                       vs30=scenario.vs30))
    for number, scenario in enumerate(NEAR_FAULT):
        seed = SEED + len(STOCHASTIC) + number
        for index in range(PER_SCENARIO):
            name = f"near_fault_{number + 1}{'abcd'[index]}"
            motion, (amplitude, period, gamma, phase, peak) = near_fault_record(scenario, seed, index)
            entries.append(SuiteRecord(name, motion, f"{name}.txt",
                                       f"synthetic, near-fault: {scenario.label}; stochastic motion plus a "
                                       f"Mavroeidis-Papageorgiou 2003 pulse of {amplitude:.3g} m/s, T_p {period:.3g} s,"
                                       f" gamma {gamma:.3g}, nu {phase:.3g} rad at {peak:.3g} s; seed {seed}-{index}",
                                       magnitude=scenario.magnitude, distance_km=scenario.distance_km,
                                       vs30=scenario.vs30, pulse_period=pulse_period(scenario.magnitude)))
    return entries


def main():
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else suite_folder("demonstration")
    written = write_suite(real_records() + synthetic_records(), folder)
    print(f"wrote {written}")


if __name__ == "__main__":
    main()
