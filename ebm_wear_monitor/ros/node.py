def main():
    print("y")
